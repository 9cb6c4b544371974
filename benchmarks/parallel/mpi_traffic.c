/* Counts the bytes every MPI rank sends, by kind of call, through MPI's
 * profiling interface (MPI standard 4.0, ch. 15: every MPI_X is also
 * PMPI_X, so a library that defines MPI_X and calls PMPI_X sees each call
 * of the program and of the libraries it loads, PETSc's included). Preloaded
 * into `fdem` by benchmarks/parallel/parallel_scaling.py:
 *
 *     mpirun -x LD_PRELOAD=libmpi_traffic.so -x FDEM_MPI_TRAFFIC=PREFIX -n 2 fdem run ...
 *
 * writes PREFIX.<rank> at MPI_Finalize: one line per kind, "kind calls bytes".
 *   p2p        point-to-point sends (ghosts, migration, PETSc's vector scatters)
 *   allreduce  MPI_Allreduce / MPI_Iallreduce: the count times the type's size
 *   allgather  MPI_Allgather(v): what this rank contributes
 *   bcast      MPI_Bcast (the root's buffer), other collectives under "other"
 * Bytes are payloads (count x type size), not what the network carries: the
 * collectives' algorithms move about log2(P) times more between P ranks.
 * Open MPI's own collectives call its internal point-to-point layer, not
 * MPI_Send, so nothing is counted twice. */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>

enum { P2P, ALLREDUCE, ALLGATHER, BCAST, OTHER, KINDS };
static const char* kind_name[KINDS] = {"p2p", "allreduce", "allgather", "bcast", "other"};
static long long calls[KINDS], bytes[KINDS];

static void count(int kind, int n, MPI_Datatype type) {
  int size = 0;
  PMPI_Type_size(type, &size);
  calls[kind] += 1;
  bytes[kind] += (long long)n * size;
}

int MPI_Send(const void* b, int n, MPI_Datatype t, int d, int tag, MPI_Comm c) {
  count(P2P, n, t);
  return PMPI_Send(b, n, t, d, tag, c);
}
int MPI_Isend(const void* b, int n, MPI_Datatype t, int d, int tag, MPI_Comm c, MPI_Request* r) {
  count(P2P, n, t);
  return PMPI_Isend(b, n, t, d, tag, c, r);
}
int MPI_Ssend(const void* b, int n, MPI_Datatype t, int d, int tag, MPI_Comm c) {
  count(P2P, n, t);
  return PMPI_Ssend(b, n, t, d, tag, c);
}
int MPI_Rsend(const void* b, int n, MPI_Datatype t, int d, int tag, MPI_Comm c) {
  count(P2P, n, t);
  return PMPI_Rsend(b, n, t, d, tag, c);
}
int MPI_Sendrecv(const void* sb, int sn, MPI_Datatype st, int d, int stag, void* rb, int rn, MPI_Datatype rt, int s,
                 int rtag, MPI_Comm c, MPI_Status* status) {
  count(P2P, sn, st);
  return PMPI_Sendrecv(sb, sn, st, d, stag, rb, rn, rt, s, rtag, c, status);
}
int MPI_Allreduce(const void* sb, void* rb, int n, MPI_Datatype t, MPI_Op op, MPI_Comm c) {
  count(ALLREDUCE, n, t);
  return PMPI_Allreduce(sb, rb, n, t, op, c);
}
int MPI_Iallreduce(const void* sb, void* rb, int n, MPI_Datatype t, MPI_Op op, MPI_Comm c, MPI_Request* r) {
  count(ALLREDUCE, n, t);
  return PMPI_Iallreduce(sb, rb, n, t, op, c, r);
}
int MPI_Reduce(const void* sb, void* rb, int n, MPI_Datatype t, MPI_Op op, int root, MPI_Comm c) {
  count(OTHER, n, t);
  return PMPI_Reduce(sb, rb, n, t, op, root, c);
}
int MPI_Allgather(const void* sb, int sn, MPI_Datatype st, void* rb, int rn, MPI_Datatype rt, MPI_Comm c) {
  count(ALLGATHER, sn, st);
  return PMPI_Allgather(sb, sn, st, rb, rn, rt, c);
}
int MPI_Allgatherv(const void* sb, int sn, MPI_Datatype st, void* rb, const int* rn, const int* displs,
                   MPI_Datatype rt, MPI_Comm c) {
  count(ALLGATHER, sn, st);
  return PMPI_Allgatherv(sb, sn, st, rb, rn, displs, rt, c);
}
int MPI_Gatherv(const void* sb, int sn, MPI_Datatype st, void* rb, const int* rn, const int* displs, MPI_Datatype rt,
                int root, MPI_Comm c) {
  count(OTHER, sn, st);
  return PMPI_Gatherv(sb, sn, st, rb, rn, displs, rt, root, c);
}
int MPI_Bcast(void* b, int n, MPI_Datatype t, int root, MPI_Comm c) {
  count(BCAST, n, t);
  return PMPI_Bcast(b, n, t, root, c);
}
int MPI_Alltoall(const void* sb, int sn, MPI_Datatype st, void* rb, int rn, MPI_Datatype rt, MPI_Comm c) {
  int ranks = 1;
  PMPI_Comm_size(c, &ranks);
  count(OTHER, sn * ranks, st);
  return PMPI_Alltoall(sb, sn, st, rb, rn, rt, c);
}
int MPI_Barrier(MPI_Comm c) {
  calls[OTHER] += 1;
  return PMPI_Barrier(c);
}

int MPI_Finalize(void) {
  const char* prefix = getenv("FDEM_MPI_TRAFFIC");
  int rank = 0;
  PMPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (prefix != NULL) {
    char path[4096];
    snprintf(path, sizeof path, "%s.%d", prefix, rank);
    FILE* f = fopen(path, "w");
    if (f != NULL) {
      for (int k = 0; k < KINDS; ++k) fprintf(f, "%s %lld %lld\n", kind_name[k], calls[k], bytes[k]);
      fclose(f);
    }
  }
  return PMPI_Finalize();
}
