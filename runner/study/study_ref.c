/*
 * study_ref.c - the force reference of rps3-study (see study_ref.h), in
 * long double and, with the same code, in double.
 */
#include <math.h>

#include "study_ref.h"

/* long double: RF(sin) is sinl */
#define REAL long double
#define S(name) name##_ld
#define RF(f) f##l
#define REF_FORCES study_ref_forces
#include "study_ref_impl.h"
#undef REAL
#undef S
#undef RF
#undef REF_FORCES

/* double */
#define REAL double
#define S(name) name##_d
#define RF(f) f
#define REF_FORCES study_ref_forces_double
#include "study_ref_impl.h"
