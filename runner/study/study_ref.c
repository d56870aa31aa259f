/*
 * study_ref.c - the force reference of rps3-study (see study_ref.h), in
 * long double and, with the same code, in double.
 */
#include <math.h>

#include "study_ref.h"

/* long double */
#define REAL long double
#define S(name) name##_ld
#define RSIN sinl
#define RCOS cosl
#define RSQRT sqrtl
#define RATAN2 atan2l
#define RTANH tanhl
#include "study_ref_impl.h"
#undef REAL
#undef S
#undef RSIN
#undef RCOS
#undef RSQRT
#undef RATAN2
#undef RTANH

/* double */
#define REAL double
#define S(name) name##_d
#define RSIN sin
#define RCOS cos
#define RSQRT sqrt
#define RATAN2 atan2
#define RTANH tanh
#include "study_ref_impl.h"

int study_ref_forces(const rps3_model *m, int effects, const double pose[3],
                     const double dpose[3], const double ddpose[3],
                     double F[3]) {
  return forces_ld(m, effects, pose, dpose, ddpose, F);
}

int study_ref_forces_double(const rps3_model *m, int effects,
                            const double pose[3], const double dpose[3],
                            const double ddpose[3], double F[3]) {
  return forces_d(m, effects, pose, dpose, ddpose, F);
}
