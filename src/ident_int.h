/*
 * ident_int.h - what the estimators of ident_fit.c and ident_consistent.c
 * share: one message-and-status path and one check of their data.
 */
#ifndef RPS3_IDENT_INT_H
#define RPS3_IDENT_INT_H

#include <stddef.h>

#include "rps3.h"

/* a message into err (may be NULL), and the status */
int rps3_ident_fail(char *err, size_t errsz, int status, const char *fmt, ...)
#ifdef __GNUC__
    __attribute__((format(printf, 4, 5)))
#endif
    ;

/* the checks of every estimator's data; need_act: each actuator must have
   rows (the two-pass weights); RPS3_OK or a status with err */
int rps3_ident_check_data(const rps3_ident_data *dt, const rps3_ident_opts *o,
                          int need_act, char *err, size_t errsz);

/* the two regressors' start and end (ident.c): d's forces unset (none is
   computed), and Y (3 x ncol) checked finite, else NaN and RPS3_ERANGE
   naming the column by name() */
void rps3_regressor_unset(rps3_data *d);
int rps3_regressor_finite(rps3_data *d, double *Y, int ncol,
                          const char *(*name)(int));

#endif /* RPS3_IDENT_INT_H */
