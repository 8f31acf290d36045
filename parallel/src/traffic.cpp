// Counting the bytes this process hands to MPI (mpi.hpp, bytes_sent), through MPI's profiling
// interface: each MPI function that sends is defined here, adds its payload to a counter and
// calls the library's own PMPI_ version. The tool exports these symbols (CMakeLists.txt), so
// the messages of PETSc and of hypre inside BoomerAMG are counted with the tool's own: what
// PETSc's -log_view reports leaves hypre's out.
//
// What counts: point-to-point messages to other processes (including persistent ones, at each
// MPI_Start), and each process's own contribution to a collective (its send buffer; for
// all-to-all, the parts addressed to others). The algorithms inside collectives move more.

#include <mpi.h>

#include <atomic>
#include <cstdint>
#include <mutex>
#include <unordered_map>

#include "rgbmesh/parallel/mpi.hpp"

namespace {

std::atomic<std::uint64_t> sent{0};

std::uint64_t bytes(int count, MPI_Datatype type) {
  if (count <= 0 || type == MPI_DATATYPE_NULL) return 0;
  int size = 0;
  PMPI_Type_size(type, &size);
  return static_cast<std::uint64_t>(count) * static_cast<std::uint64_t>(size > 0 ? size : 0);
}

int my_rank(MPI_Comm comm) {
  int r = -1;
  PMPI_Comm_rank(comm, &r);
  return r;
}

// A message to dest on comm: counted unless it stays in this process.
void to(int dest, int count, MPI_Datatype type, MPI_Comm comm) {
  if (dest == MPI_PROC_NULL || dest == my_rank(comm)) return;
  sent.fetch_add(bytes(count, type), std::memory_order_relaxed);
}

void contribute(int count, MPI_Datatype type) { sent.fetch_add(bytes(count, type), std::memory_order_relaxed); }

// Persistent sends: their payload, counted each time they start.
std::mutex persistent_mutex;
std::unordered_map<MPI_Request, std::uint64_t> persistent;

void remember(MPI_Request request, int dest, int count, MPI_Datatype type, MPI_Comm comm) {
  if (dest == MPI_PROC_NULL || dest == my_rank(comm)) return;
  const std::lock_guard<std::mutex> lock(persistent_mutex);
  persistent[request] = bytes(count, type);
}

void started(const MPI_Request& request) {
  const std::lock_guard<std::mutex> lock(persistent_mutex);
  const auto it = persistent.find(request);
  if (it != persistent.end()) sent.fetch_add(it->second, std::memory_order_relaxed);
}

std::uint64_t to_others(const int counts[], MPI_Datatype type, MPI_Comm comm) {
  int p = 0;
  PMPI_Comm_size(comm, &p);
  const int me = my_rank(comm);
  std::uint64_t total = 0;
  for (int q = 0; q < p; ++q)
    if (q != me) total += bytes(counts[q], type);
  return total;
}

}  // namespace

namespace rgbmesh::parallel {
std::uint64_t bytes_sent() { return sent.load(std::memory_order_relaxed); }
}  // namespace rgbmesh::parallel

extern "C" {

int MPI_Send(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm) {
  to(dest, count, type, comm);
  return PMPI_Send(buf, count, type, dest, tag, comm);
}
int MPI_Ssend(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm) {
  to(dest, count, type, comm);
  return PMPI_Ssend(buf, count, type, dest, tag, comm);
}
int MPI_Rsend(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm) {
  to(dest, count, type, comm);
  return PMPI_Rsend(buf, count, type, dest, tag, comm);
}
int MPI_Bsend(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm) {
  to(dest, count, type, comm);
  return PMPI_Bsend(buf, count, type, dest, tag, comm);
}
int MPI_Isend(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm, MPI_Request* r) {
  to(dest, count, type, comm);
  return PMPI_Isend(buf, count, type, dest, tag, comm, r);
}
int MPI_Issend(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm, MPI_Request* r) {
  to(dest, count, type, comm);
  return PMPI_Issend(buf, count, type, dest, tag, comm, r);
}
int MPI_Irsend(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm, MPI_Request* r) {
  to(dest, count, type, comm);
  return PMPI_Irsend(buf, count, type, dest, tag, comm, r);
}
int MPI_Ibsend(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm, MPI_Request* r) {
  to(dest, count, type, comm);
  return PMPI_Ibsend(buf, count, type, dest, tag, comm, r);
}
int MPI_Sendrecv(const void* sbuf, int scount, MPI_Datatype stype, int dest, int stag, void* rbuf, int rcount,
                 MPI_Datatype rtype, int source, int rtag, MPI_Comm comm, MPI_Status* status) {
  to(dest, scount, stype, comm);
  return PMPI_Sendrecv(sbuf, scount, stype, dest, stag, rbuf, rcount, rtype, source, rtag, comm, status);
}
int MPI_Sendrecv_replace(void* buf, int count, MPI_Datatype type, int dest, int stag, int source, int rtag,
                         MPI_Comm comm, MPI_Status* status) {
  to(dest, count, type, comm);
  return PMPI_Sendrecv_replace(buf, count, type, dest, stag, source, rtag, comm, status);
}

int MPI_Send_init(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm, MPI_Request* r) {
  const int rc = PMPI_Send_init(buf, count, type, dest, tag, comm, r);
  if (rc == MPI_SUCCESS) remember(*r, dest, count, type, comm);
  return rc;
}
int MPI_Ssend_init(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm, MPI_Request* r) {
  const int rc = PMPI_Ssend_init(buf, count, type, dest, tag, comm, r);
  if (rc == MPI_SUCCESS) remember(*r, dest, count, type, comm);
  return rc;
}
int MPI_Rsend_init(const void* buf, int count, MPI_Datatype type, int dest, int tag, MPI_Comm comm, MPI_Request* r) {
  const int rc = PMPI_Rsend_init(buf, count, type, dest, tag, comm, r);
  if (rc == MPI_SUCCESS) remember(*r, dest, count, type, comm);
  return rc;
}
int MPI_Start(MPI_Request* r) {
  started(*r);
  return PMPI_Start(r);
}
int MPI_Startall(int count, MPI_Request requests[]) {
  for (int i = 0; i < count; ++i) started(requests[i]);
  return PMPI_Startall(count, requests);
}
int MPI_Request_free(MPI_Request* r) {
  {
    const std::lock_guard<std::mutex> lock(persistent_mutex);
    persistent.erase(*r);
  }
  return PMPI_Request_free(r);
}

int MPI_Allreduce(const void* sbuf, void* rbuf, int count, MPI_Datatype type, MPI_Op op, MPI_Comm comm) {
  contribute(count, type);
  return PMPI_Allreduce(sbuf, rbuf, count, type, op, comm);
}
int MPI_Iallreduce(const void* sbuf, void* rbuf, int count, MPI_Datatype type, MPI_Op op, MPI_Comm comm,
                   MPI_Request* r) {
  contribute(count, type);
  return PMPI_Iallreduce(sbuf, rbuf, count, type, op, comm, r);
}
int MPI_Reduce(const void* sbuf, void* rbuf, int count, MPI_Datatype type, MPI_Op op, int root, MPI_Comm comm) {
  contribute(count, type);
  return PMPI_Reduce(sbuf, rbuf, count, type, op, root, comm);
}
int MPI_Scan(const void* sbuf, void* rbuf, int count, MPI_Datatype type, MPI_Op op, MPI_Comm comm) {
  contribute(count, type);
  return PMPI_Scan(sbuf, rbuf, count, type, op, comm);
}
int MPI_Exscan(const void* sbuf, void* rbuf, int count, MPI_Datatype type, MPI_Op op, MPI_Comm comm) {
  contribute(count, type);
  return PMPI_Exscan(sbuf, rbuf, count, type, op, comm);
}
int MPI_Bcast(void* buf, int count, MPI_Datatype type, int root, MPI_Comm comm) {
  if (root == my_rank(comm)) contribute(count, type);
  return PMPI_Bcast(buf, count, type, root, comm);
}
int MPI_Allgather(const void* sbuf, int scount, MPI_Datatype stype, void* rbuf, int rcount, MPI_Datatype rtype,
                  MPI_Comm comm) {
  contribute(sbuf == MPI_IN_PLACE ? rcount : scount, sbuf == MPI_IN_PLACE ? rtype : stype);
  return PMPI_Allgather(sbuf, scount, stype, rbuf, rcount, rtype, comm);
}
int MPI_Allgatherv(const void* sbuf, int scount, MPI_Datatype stype, void* rbuf, const int rcounts[],
                   const int displs[], MPI_Datatype rtype, MPI_Comm comm) {
  contribute(sbuf == MPI_IN_PLACE ? rcounts[my_rank(comm)] : scount, sbuf == MPI_IN_PLACE ? rtype : stype);
  return PMPI_Allgatherv(sbuf, scount, stype, rbuf, rcounts, displs, rtype, comm);
}
int MPI_Gather(const void* sbuf, int scount, MPI_Datatype stype, void* rbuf, int rcount, MPI_Datatype rtype,
               int root, MPI_Comm comm) {
  if (root != my_rank(comm)) contribute(scount, stype);
  return PMPI_Gather(sbuf, scount, stype, rbuf, rcount, rtype, root, comm);
}
int MPI_Gatherv(const void* sbuf, int scount, MPI_Datatype stype, void* rbuf, const int rcounts[], const int displs[],
                MPI_Datatype rtype, int root, MPI_Comm comm) {
  if (root != my_rank(comm)) contribute(scount, stype);
  return PMPI_Gatherv(sbuf, scount, stype, rbuf, rcounts, displs, rtype, root, comm);
}
int MPI_Alltoall(const void* sbuf, int scount, MPI_Datatype stype, void* rbuf, int rcount, MPI_Datatype rtype,
                 MPI_Comm comm) {
  int p = 0;
  PMPI_Comm_size(comm, &p);
  if (sbuf == MPI_IN_PLACE) {
    contribute(rcount * (p - 1), rtype);
  } else {
    contribute(scount * (p - 1), stype);
  }
  return PMPI_Alltoall(sbuf, scount, stype, rbuf, rcount, rtype, comm);
}
int MPI_Alltoallv(const void* sbuf, const int scounts[], const int sdispls[], MPI_Datatype stype, void* rbuf,
                  const int rcounts[], const int rdispls[], MPI_Datatype rtype, MPI_Comm comm) {
  if (sbuf != MPI_IN_PLACE) sent.fetch_add(to_others(scounts, stype, comm), std::memory_order_relaxed);
  return PMPI_Alltoallv(sbuf, scounts, sdispls, stype, rbuf, rcounts, rdispls, rtype, comm);
}
int MPI_Reduce_scatter_block(const void* sbuf, void* rbuf, int rcount, MPI_Datatype type, MPI_Op op, MPI_Comm comm) {
  int p = 0;
  PMPI_Comm_size(comm, &p);
  contribute(rcount * p, type);
  return PMPI_Reduce_scatter_block(sbuf, rbuf, rcount, type, op, comm);
}
int MPI_Reduce_scatter(const void* sbuf, void* rbuf, const int rcounts[], MPI_Datatype type, MPI_Op op,
                       MPI_Comm comm) {
  int p = 0;
  PMPI_Comm_size(comm, &p);
  int total = 0;
  for (int q = 0; q < p; ++q) total += rcounts[q];
  contribute(total, type);
  return PMPI_Reduce_scatter(sbuf, rbuf, rcounts, type, op, comm);
}

}  // extern "C"
