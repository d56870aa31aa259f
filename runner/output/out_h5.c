/* out_h5.c - see out_h5.h. */
#include "out_h5.h"
#include "core/h5err.h"
#include "outblock.h"

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <hdf5.h>
#include <hdf5_hl.h>

void out_fail(char *err, size_t errsz, const char *fmt, ...) {
  char h5[600], what[256];
  va_list ap;
  h5_cause(h5, sizeof h5);
  va_start(ap, fmt);
  vsnprintf(what, sizeof what, fmt, ap);
  va_end(ap);
  snprintf(err, errsz, "%s%s%s", what, h5[0] ? ": HDF5: " : "", h5);
}

int out_h5_attr_n(hid_t obj, const char *name, hid_t type, size_t n,
                  const void *v) {
  hsize_t dim = n;
  hid_t sp = n ? H5Screate_simple(1, &dim, NULL) : H5Screate(H5S_SCALAR), a;
  int rc = -1;
  if (sp < 0) return -1;
  a = H5Acreate2(obj, name, type, sp, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) {
    rc = H5Awrite(a, type, v) < 0 ? -1 : 0;
    H5Aclose(a);
  }
  H5Sclose(sp);
  return rc;
}

int out_h5_attr(hid_t obj, hid_t str, const char *name, const char *value) {
  return out_h5_attr_n(obj, name, str, 0, &value);
}

int out_h5_attrs(hid_t obj, hid_t str, const char *const (*kv)[2], size_t n) {
  size_t i;
  for (i = 0; i < n; i++)
    if (kv[i][1] &&
        ((H5Aexists(obj, kv[i][0]) > 0 && H5Adelete(obj, kv[i][0]) < 0) ||
         out_h5_attr(obj, str, kv[i][0], kv[i][1]) < 0))
      return -1;
  return 0;
}

/* the files' strings are UTF-8; HDF5 converts no character sets */
char *out_h5_read_text(hid_t loc, const char *name, int is_attr) {
  hid_t obj, str = H5Tcopy(H5T_C_S1);
  char *v = NULL, *copy = NULL;
  herr_t rc;
  if (str < 0 || H5Tset_size(str, H5T_VARIABLE) < 0 ||
      H5Tset_cset(str, H5T_CSET_UTF8) < 0 ||
      (is_attr ? H5Aexists(loc, name) : H5Lexists(loc, name, H5P_DEFAULT)) <=
          0 ||
      (obj = is_attr ? H5Aopen(loc, name, H5P_DEFAULT)
                     : H5Dopen2(loc, name, H5P_DEFAULT)) < 0) {
    H5Tclose(str);
    return NULL;
  }
  if (is_attr) {
    rc = H5Aread(obj, str, &v);
    H5Aclose(obj);
  } else {
    rc = H5Dread(obj, str, H5S_ALL, H5S_ALL, H5P_DEFAULT, &v);
    H5Dclose(obj);
  }
  if (rc >= 0 && v) {
    copy = malloc(strlen(v) + 1);
    if (copy) strcpy(copy, v);
  }
  /* the library allocated v: give it back with the library's free */
  if (v) H5free_memory(v);
  H5Tclose(str);
  return copy;
}

hid_t out_h5_dataset(hid_t file, hid_t str, const char *name, hid_t type,
                     int rank, const hsize_t *dims, const hsize_t *chunk,
                     int gzip, const void *fill, const char *units,
                     const char *doc) {
  hid_t sp = rank ? H5Screate_simple(rank, dims, NULL) : H5Screate(H5S_SCALAR);
  hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE), lcpl = H5Pcreate(H5P_LINK_CREATE);
  hid_t dapl = H5Pcreate(H5P_DATASET_ACCESS);
  hid_t ds = -1;
  if (sp < 0 || dcpl < 0 || lcpl < 0 || dapl < 0) goto done;
  /* tiles are whole chunks, written once: no chunk cache, so that memory
     does not hold a chunk per dataset */
  if (H5Pset_chunk_cache(dapl, 0, 0, 1.0) < 0) goto done;
  /* names such as manipulator.rho are plain names, no groups */
  if (chunk && H5Pset_chunk(dcpl, rank, chunk) < 0) goto done;
  if (chunk && gzip > 0 && H5Pset_deflate(dcpl, (unsigned)gzip) < 0) goto done;
  /* a checksum of each stored chunk (after deflate: of the bytes on disk),
     checked by every read: merge refuses a damaged part (verify.h); the
     strings' chunks hold heap references, which HDF5 does not checksum */
  if (chunk && H5Tis_variable_str(type) <= 0 && H5Pset_fletcher32(dcpl) < 0)
    goto done;
  if (fill && H5Pset_fill_value(dcpl, type, fill) < 0) goto done;
  if (H5Pset_char_encoding(lcpl, H5T_CSET_UTF8) < 0) goto done;
  ds = H5Dcreate2(file, name, type, sp, lcpl, dcpl, dapl);
  if (ds >= 0 && (out_h5_attr(ds, str, "units", units) < 0 ||
                  out_h5_attr(ds, str, "description", doc) < 0)) {
    H5Dclose(ds);
    ds = -1;
  }
done:
  if (sp >= 0) H5Sclose(sp);
  if (dcpl >= 0) H5Pclose(dcpl);
  if (lcpl >= 0) H5Pclose(lcpl);
  if (dapl >= 0) H5Pclose(dapl);
  return ds;
}

int out_h5_tile(hid_t ds, hid_t dxpl, hid_t type, int timed, size_t cases,
                size_t points, const void *buf, size_t c0, size_t nc, size_t k0,
                size_t nk) {
  hsize_t mdims[4], start[4] = {0, 0, 0, 0}, count[4], fstart[4] = {0, 0, 0, 0};
  hid_t fs = H5Dget_space(ds), ms = -1;
  int r, rank = fs < 0 ? -1 : H5Sget_simple_extent_dims(fs, count, NULL);
  int rc = -1;
  for (r = 0; r < rank; r++) mdims[r] = count[r];
  mdims[0] = cases;
  count[0] = nc;
  fstart[0] = c0;
  if (timed) {
    mdims[1] = points;
    count[1] = nk;
    fstart[1] = k0;
  }
  if (rank > 0) ms = H5Screate_simple(rank, mdims, NULL);
  if (ms >= 0 &&
      H5Sselect_hyperslab(ms, H5S_SELECT_SET, start, NULL, count, NULL) >= 0 &&
      H5Sselect_hyperslab(fs, H5S_SELECT_SET, fstart, NULL, count, NULL) >= 0 &&
      H5Dwrite(ds, type, ms, fs, dxpl, buf) >= 0)
    rc = 0;
  if (fs >= 0) H5Sclose(fs);
  if (ms >= 0) H5Sclose(ms);
  return rc;
}

hid_t out_h5_scale(hid_t file, hid_t str, const char *name, hid_t type,
                   size_t n, const void *data, const char *units,
                   const char *doc) {
  hsize_t dim = n;
  hid_t ds =
      out_h5_dataset(file, str, name, type, 1, &dim, NULL, 0, NULL, units, doc);
  if (ds < 0) return -1;
  if ((data && H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) ||
      H5DSset_scale(ds, name) < 0) {
    H5Dclose(ds);
    return -1;
  }
  return ds;
}

void out_utc_now(char now[32]) {
  time_t t = time(NULL);
  struct tm tm;
  gmtime_r(&t, &tm);
  strftime(now, 32, "%Y-%m-%dT%H:%M:%SZ", &tm);
}

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
    hid_t type = (ki->type == KEY_REAL || scene_key_ncomp(ki))
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
