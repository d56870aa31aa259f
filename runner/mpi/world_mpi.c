/* world_mpi.c - world.h over Open MPI, on MPI_COMM_WORLD (rps3-run-mpi). */
#include "world.h"

#include <time.h>

#include <mpi.h>

int world_has_mpi(void) { return 1; }

void world_init(int *argc, char ***argv, world *w) {
  int provided;
  /* worker threads (-j) never call MPI */
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &w->rank);
  MPI_Comm_size(MPI_COMM_WORLD, &w->size);
}

void world_finalize(void) { MPI_Finalize(); }

void world_abort(int code) { MPI_Abort(MPI_COMM_WORLD, code); }

void world_idle_barrier(void) {
  MPI_Request rq;
  struct timespec nap = {0, 1000000};
  int done = 0;
  MPI_Ibarrier(MPI_COMM_WORLD, &rq);
  for (;;) {
    MPI_Test(&rq, &done, MPI_STATUS_IGNORE);
    if (done) break;
    nanosleep(&nap, NULL);
  }
}

void world_max_int(const int *in, int *out, int n) {
  MPI_Allreduce(in, out, n, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
}

void world_sum_ulong(const unsigned long *in, unsigned long *out, int n) {
  MPI_Reduce(in, out, n, MPI_UNSIGNED_LONG, MPI_SUM, 0, MPI_COMM_WORLD);
}

void world_gather(const char *mine, size_t size, char *all) {
  MPI_Gather(mine, (int)size, MPI_CHAR, all, (int)size, MPI_CHAR, 0,
             MPI_COMM_WORLD);
}

void world_bcast_int(int *v) { MPI_Bcast(v, 1, MPI_INT, 0, MPI_COMM_WORLD); }
