/*
 * design_int.h - what design.c lends design_eval.c: the design's validation
 * into a model, reporting the field by identifier.
 */
#ifndef RPS3_DESIGN_INT_H
#define RPS3_DESIGN_INT_H

#include "rps3.h"

/* rps3_design_model with the failure in chk (chk->field a design field) */
int rps3_design_model_check(const rps3_design *ds, rps3_model *m,
                            rps3_check *chk);

#endif
