/* world_stub.c - world.h without MPI (rps3-run): a world of one process,
   rank 0 of 1, whose collectives copy their input. */
#include "world.h"

#include <stdlib.h>
#include <string.h>

int world_has_mpi(void) { return 0; }

void world_init(int *argc, char ***argv, world *w) {
  (void)argc;
  (void)argv;
  w->rank = 0;
  w->size = 1;
}

void world_finalize(void) {}

void world_abort(int code) { exit(code); }

void world_idle_barrier(void) {}

void world_max_int(const int *in, int *out, int n) {
  memcpy(out, in, (size_t)n * sizeof *in);
}

void world_sum_ulong(const unsigned long *in, unsigned long *out, int n) {
  memcpy(out, in, (size_t)n * sizeof *in);
}

void world_gather(const char *mine, size_t size, char *all) {
  memcpy(all, mine, size);
}

void world_bcast_int(int *v) { (void)v; }
