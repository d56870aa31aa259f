/*
 * study_ref.h - the force reference of rps3-study: inverse dynamics by a
 * formulation of its own (Kane's equations in the pose coordinates, with
 * exact time derivatives by second-order jets), evaluated in long double
 * from the model's input fields only, so that it grades the library
 * instead of agreeing with it by construction.
 */
#ifndef RPS3_STUDY_REF_H
#define RPS3_STUDY_REF_H

#include "rps3.h"

/*
 * Forces F [N] of the effects selected in `effects` (RPS3_EFF_* bits) at
 * the state (pose, dpose, ddpose), for model m.  Reads only m's inputs (R,
 * rho, M, m, d, link_Ic, g, payload, friction), never a derived field.
 * study_ref_forces works in long double; study_ref_forces_double is the
 * same code in double, whose distance from the long double result measures
 * how much the formulation amplifies rounding (the reference's own floor is
 * that distance times LDBL_EPSILON / DBL_EPSILON).  Returns 0, or -1 when
 * the pose is not reachable or the equations are singular.
 */
int study_ref_forces(const rps3_model *m, int effects, const double pose[3],
                     const double dpose[3], const double ddpose[3],
                     double F[3]);
int study_ref_forces_double(const rps3_model *m, int effects,
                            const double pose[3], const double dpose[3],
                            const double ddpose[3], double F[3]);

#endif
