/* out_cf.c - see out_cf.h. */
#include "out_cf.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hdf5_hl.h>

#include "out_h5.h"
#include "outblock.h"

/* a CF flag: its value (or mask) and its word */
typedef struct {
  int32_t value;
  const char *meaning;
} flag_word;

/* the statuses a case can end with, as CF flag words: every rps3_status
   (include/rps3.h; tests/test_cf.py checks that none is missing against
   rps3_strerror) and the runner's "not computed" */
static const flag_word status_flags[] = {
    {RPS3_OK, "ok"},
    {RPS3_EREACH, "pose_unreachable"},
    {RPS3_ENOCONV, "theta_solve_not_converged"},
    {RPS3_EBRANCH, "theta_outside_branch"},
    {RPS3_ESING, "singular_configuration"},
    {RPS3_EDOMAIN, "time_outside_span"},
    {RPS3_ERANGE, "result_not_finite"},
    {RPS3_EMODE, "other_assembly_mode"},
    {RPS3_EEMPTY, "empty_workspace"},
    {RPS3_EINVAL, "invalid_argument"},
    {RPS3_ENOMEM, "out_of_memory"},
    {RPS3_ESTATE, "stage_out_of_order"},
    {OUT_STATUS_NOT_COMPUTED, "not_computed"}};

/* the warning bits of `warn` (enum rps3_warning) */
static const flag_word warn_flags[] = {
    {RPS3_WARN_ILLCOND, "lambda_system_ill_conditioned"},
    {RPS3_WARN_ALPHA, "alpha_undefined"},
    {RPS3_WARN_MODE, "assembly_mode_changed"},
    {RPS3_WARN_TRANS, "transmission_above_warn"}};

#define NSTATUS (sizeof status_flags / sizeof status_flags[0])
#define NWARN (sizeof warn_flags / sizeof warn_flags[0])

/* "NOW COMMAND (rps3 VERSION, git REVISION)" (malloc'd) */
static char *history_line(const char *now, const char *command_line) {
  size_t len = strlen(now) + strlen(command_line) + strlen(rps3_version()) +
               strlen(rps3_git_revision) + 32;
  char *line = malloc(len);
  if (line)
    snprintf(line, len, "%s %s (rps3 %s, git %s)", now, command_line,
             rps3_version(), rps3_git_revision);
  return line;
}

int out_cf_root(hid_t file, hid_t str, const char *now,
                const char *command_line) {
  char *line = history_line(now, command_line);
  const char *const kv[][2] = {{"Conventions", OUT_CF_CONVENTIONS},
                               {"git_revision", rps3_git_revision},
                               {"history", line}};
  int rc = line ? out_h5_attrs(file, str, kv, 3) : -1;
  free(line);
  return rc;
}

/* append a history line for a command that rewrote the file (merge) */
static int history_add(hid_t file, hid_t str, const char *now,
                       const char *command_line) {
  char *old = out_h5_read_text(file, "history", 1),
       *line = history_line(now, command_line);
  char *all = NULL;
  int rc = -1;
  /* CF: one line per program that made or changed the file, oldest
     first */
  if (line) {
    size_t len = (old ? strlen(old) + 1 : 0) + strlen(line) + 1;
    all = malloc(len);
    if (all) {
      snprintf(all, len, "%s%s%s", old ? old : "", old ? "\n" : "", line);
      const char *const kv[][2] = {{"history", all}};
      rc = out_h5_attrs(file, str, kv, 1);
    }
  }
  free(old);
  free(line);
  free(all);
  return rc;
}

int out_cf_long_name(hid_t ds, hid_t str, const char *long_name) {
  return out_h5_attr(ds, str, "long_name", long_name);
}

/* flag_values (a status) or flag_masks (the warning bits, the
   reachability flags), and flag_meanings */
static int flags(hid_t ds, hid_t str, out_flags kind) {
  const flag_word *tab = kind == OUT_FLAGS_STATUS ? status_flags : warn_flags;
  int32_t v[NSTATUS + RPS3_DESIGN_NFLAG];
  char words[512];
  size_t k, len = 0,
            n = kind == OUT_FLAGS_STATUS ? NSTATUS
                : kind == OUT_FLAGS_WARN ? NWARN
                                         : RPS3_DESIGN_NFLAG;
  words[0] = '\0';
  for (k = 0; k < n && len < sizeof words; k++) {
    int reach = kind == OUT_FLAGS_REACH;
    v[k] = reach ? (int32_t)1 << k : tab[k].value;
    len += (size_t)snprintf(
        words + len, sizeof words - len, "%s%s", k ? " " : "",
        reach ? rps3_design_flag_name((int)k) : tab[k].meaning);
  }
  return out_h5_attr_n(ds,
                       kind == OUT_FLAGS_STATUS ? "flag_values" : "flag_masks",
                       H5T_NATIVE_INT32, n, v) < 0 ||
                 out_h5_attr(ds, str, "flag_meanings", words) < 0
             ? -1
             : 0;
}

int out_cf_field(hid_t ds, hid_t str, int i) {
  if (out_cf_long_name(ds, str, out_field_table[i].long_name) < 0) return -1;
  if (out_field_table[i].flags == OUT_FLAGS_NONE) return 0;
  return flags(ds, str, out_field_table[i].flags);
}

int out_cf_time(hid_t ds, hid_t str) {
  /* the calendar of the nominal reference date: proleptic Gregorian,
     which every reader decodes */
  static const char *const kv[][2] = {{"standard_name", "time"},
                                      {"calendar", "proleptic_gregorian"},
                                      {"axis", "T"}};
  return out_h5_attrs(ds, str, kv, 3);
}

/* the variable name of a swept scene key: CF names are made of letters,
   digits and underscores (CF-1.10 section 2.3), so "." is written "__"
   and "[k]" "_k" ("trajectory.amp[2]" -> "trajectory__amp_2"; the same
   mapping in python/rps3/h5io.py, key_name); into buf */
static const char *key_name(const char *key, char *buf, size_t sz) {
  size_t n = 0;
  const char *c;
  for (c = key; *c && n + 2 < sz; c++) {
    if (*c == '.') {
      buf[n++] = '_';
      buf[n++] = '_';
    } else if (*c == '[')
      buf[n++] = '_';
    else if (*c != ']')
      buf[n++] = *c;
  }
  buf[n] = '\0';
  return buf;
}

/* a controller gain's unit is "A or B" (scene_sim.h): A for pd and
   pd_gravity (a force per error), B for computed_torque (an
   acceleration per error).  When every case's controller is of one family,
   buf becomes that unit, which UDUNITS parses; a sweep of controllers of
   both families keeps "A or B" (one variable has one unit:
   docs/hdf5.md) */
static const char *gain_units(const scene *s, char *buf) {
  char *alt = strstr(buf, " or ");
  int family = -1, f;
  size_t a, i;
  if (!alt) return buf;
  family = s->base.sim.controller == RPS3_CTRL_COMPUTED_TORQUE;
  for (a = 0; a < s->naxis; a++)
    if (s->axis[a].key == K_SIM_CONTROLLER)
      for (i = 0, family = -1; i < s->axis[a].n; i++) {
        f = (int)s->axis[a].val[i] == RPS3_CTRL_COMPUTED_TORQUE;
        if (family >= 0 && f != family) return buf;
        family = f;
      }
  if (family == 1)
    memmove(buf, alt + 4, strlen(alt + 4) + 1);
  else
    *alt = '\0';
  return buf;
}

/* the UDUNITS-2 units of sweep axis a of s into buf: the component's unit
   of a list key ("rad, rad, m"[2] -> "m"), "1" for dimensionless keys,
   enums and bools */
static const char *axis_units(const scene *s, size_t a, char *buf, size_t sz) {
  const scene_axis *ax = &s->axis[a];
  const scene_key_info *ki = scene_key_get(ax->key);
  const char *u = ki->f->unit;
  int k;
  if (ki->type == KEY_ENUM || ki->type == KEY_BOOL || strcmp(u, "-") == 0) {
    snprintf(buf, sz, "1");
    return buf;
  }
  /* "rad, rad, m": the unit of component comp */
  for (k = 0; k < ax->comp && strchr(u, ','); k++)
    u = strchr(u, ',') + 1 + (strchr(u, ',')[1] == ' ');
  snprintf(buf, sz, "%.*s", (int)strcspn(u, ","), u);
  return gain_units(s, buf);
}

char *out_h5_coordinates(const scene *s, int with_case_time) {
  size_t a, len = 1;
  char *c, name[160];
  for (a = 0; a < s->naxis; a++)
    len += strlen(key_name(s->axis[a].path, name, sizeof name)) + 1;
  len += with_case_time ? strlen(" case_time") : 0;
  c = malloc(len);
  if (!c) return NULL;
  c[0] = '\0';
  for (a = 0; a < s->naxis; a++) {
    if (a) strcat(c, " ");
    strcat(c, key_name(s->axis[a].path, name, sizeof name));
  }
  if (with_case_time) strcat(c, s->naxis ? " case_time" : "case_time");
  return c;
}

int out_stamp(hid_t file, const char *command_line) {
  char now[32];
  const char *const kv[][2] = {{"created_utc", now},
                               {"command_line", command_line}};
  hid_t str = H5Tcopy(H5T_C_S1);
  int rc = -1;
  out_utc_now(now);
  if (str >= 0 && H5Tset_size(str, H5T_VARIABLE) >= 0 &&
      H5Tset_cset(str, H5T_CSET_UTF8) >= 0 &&
      out_h5_attrs(file, str, kv, 2) >= 0 &&
      history_add(file, str, now, command_line) >= 0)
    rc = 0;
  if (str >= 0) H5Tclose(str);
  return rc;
}

/* the swept values of axis a, case by case, in runs of OUT_AXIS_RUN
   cases: an enum's names, else the values (an int key's whole numbers
   convert exactly to its int32) */
static int swept_values(hid_t ds, hid_t str, const scene *s, size_t a) {
  const scene_axis *ax = &s->axis[a];
  int is_enum = scene_key_get(ax->key)->type == KEY_ENUM, rc = 0;
  size_t c0, i, n;
  void *buf = malloc(OUT_AXIS_RUN * sizeof(double));
  for (c0 = 0; buf && c0 < s->ncase && rc == 0; c0 += n) {
    n = s->ncase - c0 < OUT_AXIS_RUN ? s->ncase - c0 : OUT_AXIS_RUN;
    for (i = 0; i < n; i++) {
      double x = ax->val[scene_case_coord(s, c0 + i, a)];
      if (is_enum)
        ((const char **)buf)[i] = scene_enum_name(ax->key, (int)x);
      else
        ((double *)buf)[i] = x;
    }
    rc = out_h5_tile(ds, H5P_DEFAULT, is_enum ? str : H5T_NATIVE_DOUBLE, 0, n,
                     1, buf, c0, n, 0, 1);
  }
  free(buf);
  return buf ? rc : -1;
}

int out_cf_swept_keys(hid_t file, hid_t str, const scene *s, hid_t dcase,
                      size_t *bad) {
  size_t a;
  for (a = 0; a < s->naxis; a++) {
    const scene_key_info *ki = scene_key_get(s->axis[a].key);
    char doc[400], units[32], name[160], long_name[160];
    const char *const kv[][2] = {{"long_name", long_name},
                                 {"scene_key", s->axis[a].path}};
    hsize_t nc = s->ncase;
    hid_t type = (ki->type == KEY_REAL || ki->type == KEY_REAL3)
                     ? H5T_NATIVE_DOUBLE
                 : ki->type == KEY_ENUM ? str
                                        : H5T_NATIVE_INT32;
    hid_t ds;
    int fail;
    snprintf(doc, sizeof doc, "swept scene key %s: %s (paper: %s)",
             s->axis[a].path, ki->doc, ki->symbol);
    snprintf(long_name, sizeof long_name, "swept scene key %s",
             s->axis[a].path);
    /* the variable has the key's CF name, the key in scene_key */
    ds = out_h5_dataset(file, str, key_name(s->axis[a].path, name, sizeof name),
                        type, 1, &nc, NULL, 0, NULL,
                        axis_units(s, a, units, sizeof units), doc);
    fail = ds < 0 || out_h5_attrs(ds, str, kv, 2) < 0 ||
           H5DSattach_scale(ds, dcase, 0) < 0 ||
           swept_values(ds, str, s, a) < 0;
    if (ds >= 0) H5Dclose(ds);
    if (fail) {
      if (bad) *bad = a;
      return -1;
    }
  }
  return 0;
}
