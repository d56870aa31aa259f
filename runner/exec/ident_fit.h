/*
 * ident_fit.h - one fit of an identification's plan (ident_plan.h): the
 * WLS of its columns and, when asked, the consistent fit (the paper
 * layout restricted to the fitted columns, or the general layout's
 * bodies), and the held-out prediction of both.
 */
#ifndef RPS3_RUNNER_IDENT_FIT_H
#define RPS3_RUNNER_IDENT_FIT_H

#include <stddef.h>

#include "ident_plan.h"

/* Fit forces F (n) with the plan's method (and the consistent fit when
   `consistent`) into r; r->status the fit's.  Allocates (GSL): not for a
   per-point path. */
void ident_fit_run(const ident_plan *p, const double *F, int consistent,
                   ident_fit *r);

/* ident_fit_run on the first n rows of the plan (Y, Ylay) and F */
void ident_fit_rows(const ident_plan *p, const double *F, size_t n,
                    int consistent, ident_fit *r);

/* The held-out NRMSE of fit r on rows [p->nfit, p->n) of forces F: the
   RMS of the prediction minus F over the RMS of F, the prediction Y theta
   (wls) and that of the consistent fit (general: Ylay times its layout
   parameters) in cons; NaN for a fit that failed, none held out, or a
   consistent fit not run. */
void ident_holdout_nrmse(const ident_plan *p, const double *F,
                         const ident_fit *r, double *wls, double *cons);

/* free what ident_fit_run allocated (r may be zeroed) */
void ident_fit_free(ident_fit *r);

#endif /* RPS3_RUNNER_IDENT_FIT_H */
