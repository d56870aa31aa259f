/*
 * design.c - a design (geometry, joint limits, mass model), its field
 * table, its validation and model, and the grids of poses it is rated on;
 * design_eval.c rates it over a set of poses (reachability, force
 * transmission (LTI), homogeneous conditioning, parasitic motion) and
 * design_task.c along a task (actuator force and power).  The positions are
 * rps3_inverse's (one formula of each quantity in the library); this file
 * adds only what it measures on them.  docs/design.md has the definitions.
 */
#include <stdlib.h>
#include <string.h>

#include "internal.h"

/* ------------------------------------------------------------------ fields */

#define DROW(ID, MEMBER, LO, LO_OPEN, HI, UNIT, NAME)                          \
  {NAME, RPS3_IN_DESIGN, offsetof(rps3_design, MEMBER), 1, 0, LO, LO_OPEN, HI, \
   UNIT},
static const rps3_field_info dfields[RPS3_NDESIGN_FIELD] = {
    RPS3_DESIGN_FIELDS(DROW)};
#undef DROW

const rps3_field_info *rps3_design_field(int id) {
  return (id >= 0 && id < RPS3_NDESIGN_FIELD) ? &dfields[id] : NULL;
}

static const char *const flag_names[RPS3_DESIGN_NFLAG] = {
    "stroke", "pin", "ball", "interference", "assembly", "singular"};

const char *rps3_design_flag_name(int k) {
  return (k >= 0 && k < RPS3_DESIGN_NFLAG) ? flag_names[k] : NULL;
}

/* record a failure of design field id: "NAME = VALUE: why" */
static int dfail(rps3_check *chk, int id, double value, int rel,
                 const char *why) {
  if (chk != NULL) {
    chk->field = id;
    chk->comp = 0;
    chk->related[0] = rel;
    chk->related[1] = -1;
    snprintf(chk->msg, sizeof chk->msg, "%s = %.16g: %.180s", dfields[id].name,
             value, why);
  }
  return RPS3_EINVAL;
}

static double dvalue(const rps3_design *ds, int id) {
  return *(const double *)((const char *)ds + dfields[id].offset);
}

/* the link mass model of rps3_design (rps3.h): m, d, link_Ic */
static void link_mass(const rps3_design *ds, double *m, double *d, double *ic) {
  double rod = ds->link_density * ds->l_max; /* the rod's mass */
  double h = 0.5 * ds->l_max;                /* its centroid */
  *m = ds->actuator_mass + rod;
  *d = *m > 0.0 ? (ds->actuator_mass * ds->actuator_d + rod * h) / *m : 0.0;
  *ic = rod * ds->l_max * ds->l_max / 12.0 + rod * (h - *d) * (h - *d) +
        ds->actuator_mass * (ds->actuator_d - *d) * (ds->actuator_d - *d);
}

void rps3_design_default(rps3_design *ds) {
  if (ds == NULL) return;
  memset(ds, 0, sizeof(*ds));
  /* Table II */
  ds->R = 0.2286;
  ds->rho = 0.5;
  ds->M = 0.18;
  ds->actuator_mass = 0.09;
  ds->actuator_d = 0.1524;
  ds->link_density = 0.0;
  /* limits the paper does not give: a stroke holding its helix */
  ds->l_min = 0.2286;
  ds->l_max = 2.0 * 0.2286;
  ds->theta_min = 0.0;
  ds->theta_max = RPS3_PI;
  ds->ball_max = 0.25 * RPS3_PI;
  ds->link_radius = 0.0;
  ds->payload = 0.0;
  ds->payload_height = 0.0;
  ds->g = 9.80665;
}

void rps3_design_opts_default(rps3_design_opts *o) {
  if (o == NULL) return;
  o->lti_good = 0.7;
  o->length = 0.0;
  o->cond_sing = 1e8;
}

/* the model fields rps3_model_init may name, as design fields */
static int design_id_of_model(int f) {
  switch (f) {
  case RPS3_F_R: return RPS3_DF_R;
  case RPS3_F_RHO: return RPS3_DF_RHO;
  case RPS3_F_PLATFORM_MASS: return RPS3_DF_M;
  case RPS3_F_LINK_MASS: return RPS3_DF_ACTUATOR_MASS;
  case RPS3_F_D: return RPS3_DF_ACTUATOR_D;
  case RPS3_F_LINK_IC: return RPS3_DF_LINK_DENSITY;
  case RPS3_F_G: return RPS3_DF_G;
  case RPS3_F_PAYLOAD_MASS: return RPS3_DF_PAYLOAD;
  case RPS3_F_PAYLOAD_COM: return RPS3_DF_PAYLOAD_HEIGHT;
  default: return -1;
  }
}

/* validate ds and fill m (initialised) */
int rps3_design_model(const rps3_design *ds, rps3_model *m, rps3_check *chk) {
  rps3_check mchk;
  double lm, ld, lic;
  int id;
  rps3_check_clear(chk);
  if (ds == NULL || m == NULL) {
    if (chk != NULL)
      snprintf(chk->msg, sizeof chk->msg, "%s is NULL",
               ds == NULL ? "design" : "model");
    return RPS3_EINVAL;
  }
  /* each field against its range (RPS3_DESIGN_FIELDS) */
  for (id = 0; id < RPS3_NDESIGN_FIELD; id++) {
    const rps3_field_info *f = &dfields[id];
    double x = dvalue(ds, id);
    if (!rps3_field_in_range(f, x)) {
      char why[96];
      if (f->hi == HUGE_VAL)
        snprintf(why, sizeof why, "must be finite and %s %g",
                 f->lo_open ? ">" : ">=", f->lo);
      else
        snprintf(why, sizeof why, "must be finite and in %s%g, %g]",
                 f->lo_open ? "(" : "[", f->lo, f->hi);
      if (f->lo == -HUGE_VAL) snprintf(why, sizeof why, "must be finite");
      return dfail(chk, id, x, -1, why);
    }
  }
  /* the rules between fields: bounds in order, with room between them */
  if (!(ds->l_max > ds->l_min)) {
    char why[128];
    snprintf(why, sizeof why,
             "must be > l_min = %.16g (the stroke l_max - l_min is %.3g m, "
             "it must be > 0)",
             ds->l_min, ds->l_max - ds->l_min);
    return dfail(chk, RPS3_DF_L_MAX, ds->l_max, RPS3_DF_L_MIN, why);
  }
  if (!(ds->theta_max > ds->theta_min)) {
    char why[128];
    snprintf(why, sizeof why,
             "must be > theta_min = %.16g (an empty pin joint range)",
             ds->theta_min);
    return dfail(chk, RPS3_DF_THETA_MAX, ds->theta_max, RPS3_DF_THETA_MIN, why);
  }
  link_mass(ds, &lm, &ld, &lic);
  if (!(isfinite(lm) && isfinite(ld) && isfinite(lic)))
    return dfail(chk, RPS3_DF_LINK_DENSITY, ds->link_density, RPS3_DF_L_MAX,
                 "the link mass, centroid or inertia (link_density l_max, "
                 "l_max^3) overflows");

  rps3_model_default(m);
  m->R = ds->R;
  m->rho = ds->rho;
  m->M = ds->M;
  m->m = lm;
  m->d = ld;
  m->link_Ic = lic;
  m->g = ds->g;
  m->payload.mass = ds->payload;
  m->payload.com[2] = ds->payload_height;
  if (ds->payload > 0.0) m->opt.effects |= RPS3_EFF_PAYLOAD;
  if (rps3_model_init(m, &mchk) != RPS3_OK) {
    /* a product that overflows (M g, m d^2, ...): name the design's
       field behind the model's */
    int did = design_id_of_model(mchk.field);
    if (did < 0) {
      if (chk != NULL) *chk = mchk;
      return RPS3_EINVAL;
    }
    return dfail(chk, did, dvalue(ds, did), -1,
                 strchr(mchk.msg, ':') ? strchr(mchk.msg, ':') + 2 : mchk.msg);
  }
  return RPS3_OK;
}

/* ------------------------------------------------------------------- grid */

static int grid_ok(const rps3_design_grid *gr) {
  int k;
  if (gr == NULL) return 0;
  for (k = 0; k < 3; k++)
    if (!(isfinite(gr->lo[k]) && isfinite(gr->hi[k]) &&
          gr->hi[k] >= gr->lo[k] && gr->n[k] >= 1))
      return 0;
  return 1;
}

void rps3_design_grid_default(const rps3_design *ds, rps3_design_grid *gr) {
  double R = (ds != NULL) ? ds->R : 0.2286;
  if (gr == NULL) return;
  gr->lo[0] = -RPS3_PI;
  gr->hi[0] = RPS3_PI;
  gr->lo[1] = 0.0;
  gr->hi[1] = RPS3_PI / 3.0;
  gr->lo[2] = 0.0;
  gr->hi[2] = 2.0 * R;
  gr->n[0] = gr->n[1] = gr->n[2] = 10;
}

size_t rps3_design_grid_size(const rps3_design_grid *gr) {
  size_t n01;
  if (gr == NULL || gr->n[0] == 0 || gr->n[1] == 0 || gr->n[2] == 0) return 0;
  if (gr->n[1] > (size_t)-1 / gr->n[0]) return 0;
  n01 = gr->n[0] * gr->n[1];
  if (gr->n[2] > (size_t)-1 / n01) return 0;
  return n01 * gr->n[2];
}

int rps3_design_grid_pose(const rps3_design_grid *gr, size_t i,
                          double pose[3]) {
  size_t j[3];
  int k;
  if (!grid_ok(gr) || pose == NULL || i >= rps3_design_grid_size(gr))
    return RPS3_EINVAL;
  j[0] = i % gr->n[0];
  j[1] = (i / gr->n[0]) % gr->n[1];
  j[2] = i / gr->n[0] / gr->n[1];
  for (k = 0; k < 3; k++)
    pose[k] = gr->lo[k] +
              ((double)j[k] + 0.5) * (gr->hi[k] - gr->lo[k]) / (double)gr->n[k];
  return RPS3_OK;
}

int rps3_design_grid_cell(const rps3_design_grid *gr, double *volume) {
  int k;
  double v = 1.0;
  if (!grid_ok(gr) || volume == NULL) return RPS3_EINVAL;
  for (k = 0; k < 3; k++) v *= (gr->hi[k] - gr->lo[k]) / (double)gr->n[k];
  *volume = v;
  return RPS3_OK;
}
