/*
 * error.c - version, status strings, effect, output and solver names.
 */
#include <string.h>

#include "internal.h"

const char *rps3_version(void) { return RPS3_VERSION_STRING; }

/* Empty on purpose: a place for a debugger breakpoint on any library error. */
void rps3_error_hook(int code) { (void)code; }

const char *rps3_strerror(int status) {
  switch (status) {
  case RPS3_OK: return "success";
  case RPS3_EREACH: return "pose unreachable";
  case RPS3_ENOCONV: return "theta solve did not converge";
  case RPS3_EBRANCH: return "theta solve converged outside 0 < theta < pi";
  case RPS3_ESING: return "singular configuration";
  case RPS3_EDOMAIN: return "time outside the trajectory span";
  case RPS3_ERANGE: return "result not finite (overflow)";
  case RPS3_EMODE: return "theta solve found another assembly mode";
  case RPS3_EEMPTY: return "empty workspace: no pose reachable";
  case RPS3_EINVAL: return "invalid argument";
  case RPS3_ENOMEM: return "out of memory";
  case RPS3_ESTATE: return "stage called before the stage it depends on";
  default: return "unknown status";
  }
}

/* index k is bit 1 << k of enum rps3_effect */
static const char *const effect_names[RPS3_NEFFECT] = {
    "platform_gravity", "link_gravity", "platform_inertia",
    "link_inertia",     "payload",      "pin_friction",
    "prismatic_friction"};

const char *rps3_effect_name(int k) {
  return (k >= 0 && k < RPS3_NEFFECT) ? effect_names[k] : NULL;
}

int rps3_effect_index(const char *name) {
  int k;
  if (name == NULL) return -1;
  for (k = 0; k < RPS3_NEFFECT; k++)
    if (strcmp(name, effect_names[k]) == 0) return k;
  return -1;
}

/* index k is bit 1 << k of enum rps3_output */
static const char *const output_names[RPS3_NOUTPUT] = {
    "forces", "effects", "theta", "lambda", "transmission", "certify"};

const char *rps3_output_name(int k) {
  return (k >= 0 && k < RPS3_NOUTPUT) ? output_names[k] : NULL;
}

int rps3_output_index(const char *name) {
  return rps3_name_lookup(output_names, RPS3_NOUTPUT, name);
}

static const char *const solver_names[RPS3_NSOLVER] = {
    "hybridsj", "hybridj", "newton",  "gnewton",
    "hybrids",  "hybrid",  "dnewton", "broyden"};

const char *rps3_solver_name(int solver) {
  return (solver >= 0 && solver < RPS3_NSOLVER) ? solver_names[solver] : NULL;
}

int rps3_solver_index(const char *name) {
  int k;
  if (name == NULL) return -1;
  for (k = 0; k < RPS3_NSOLVER; k++)
    if (strcmp(name, solver_names[k]) == 0) return k;
  return -1;
}

int rps3_first_nonfinite(const double *a, int n) {
  int k;
  for (k = 0; k < n; k++)
    if (!isfinite(a[k])) return k;
  return -1;
}
