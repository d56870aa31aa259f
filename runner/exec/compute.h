/* compute.h - one case of a sweep, self-contained: its own workspace, its
   own slot of the output block. */
#ifndef RPS3_RUNNER_COMPUTE_H
#define RPS3_RUNNER_COMPUTE_H

#include <stddef.h>

#include "output/output.h"
#include "scene/scene.h"

/* Compute samples [k0, k0 + nk) of case c into slot `slot` of b with the
   workspace d (allocated for c's solver): the trajectory, then the
   pipeline.  k0 == 0 starts the case (rps3_data_reset: no warm start leaks
   from the previous case).  Returns RPS3_OK, or the status of the first
   failing sample with *failed_at its time index and the reason in
   b->msg[slot]; the samples after it are not computed. */
int case_compute(const scene_case *c, rps3_data *d, size_t k0, size_t nk,
                 out_block *b, size_t slot, size_t *failed_at);

/* The workspace for case c in ws, one per solver kind, allocated on first
   use; NULL with err when it cannot be.  case_workspaces_free frees ws. */
rps3_data *case_workspace(rps3_data *ws[RPS3_NSOLVER], const scene_case *c,
                          char *err, size_t errsz);
void case_workspaces_free(rps3_data *ws[RPS3_NSOLVER]);

#endif /* RPS3_RUNNER_COMPUTE_H */
