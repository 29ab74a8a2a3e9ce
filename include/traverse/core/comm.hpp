#pragma once
// The MPI calls of traverse, also for a process without MPI: MPI_COMM_NULL stands for this
// process alone, MPI not started (check outside a launcher: docs/developer.md, "Start-up").
// Alone, a reduction or a gather is a copy, a broadcast or a barrier nothing, rank 0 of size 1.
// Header only.
#include <mpi.h>

#include <algorithm>
#include <cstring>

namespace traverse::par {

/// This process alone, MPI not started.
inline bool alone(MPI_Comm comm) { return comm == MPI_COMM_NULL; }
inline int rank(MPI_Comm comm) {
  int r = 0;
  if (!alone(comm)) MPI_Comm_rank(comm, &r);
  return r;
}
inline int size(MPI_Comm comm) {
  int n = 1;
  if (!alone(comm)) MPI_Comm_size(comm, &n);
  return n;
}
/// MPI_Allreduce of n values of `type` (`in` and `out` may be the same array).
template <class T>
void allreduce(const T* in, T* out, int n, MPI_Datatype type, MPI_Op op, MPI_Comm comm) {
  if (alone(comm)) {
    if (in != out) std::copy(in, in + n, out);
    return;
  }
  if (in == out) MPI_Allreduce(MPI_IN_PLACE, out, n, type, op, comm);
  else MPI_Allreduce(in, out, n, type, op, comm);
}
inline void bcast(void* data, int n, MPI_Datatype type, int root, MPI_Comm comm) {
  if (!alone(comm)) MPI_Bcast(data, n, type, root, comm);
}
/// Rank 0's `answer` on every rank of `comm` (what the others pass is ignored). Collective.
inline bool root_answer(bool answer, MPI_Comm comm) {
  int a = answer ? 1 : 0;
  bcast(&a, 1, MPI_INT, 0, comm);
  return a != 0;
}
inline void barrier(MPI_Comm comm) {
  if (!alone(comm)) MPI_Barrier(comm);
}
/// Every rank's `bytes` bytes of `mine`, in rank order, into `all`.
inline void allgather_bytes(const void* mine, int bytes, void* all, MPI_Comm comm) {
  if (alone(comm)) {
    std::memcpy(all, mine, static_cast<std::size_t>(bytes));
    return;
  }
  MPI_Allgather(mine, bytes, MPI_BYTE, all, bytes, MPI_BYTE, comm);
}

}  // namespace traverse::par
