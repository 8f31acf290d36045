// rgbmesh::parallel with MPI (mpi.hpp). The distributed solves go through fem's PETSc module
// (rgbmesh/fem/petsc_module.hpp), loaded by initialize: no source here sees PETSc.

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "rgbmesh/detail/parallel_for.hpp"
#include "rgbmesh/fem/petsc_module.hpp"
#include "rgbmesh/parallel/mpi.hpp"
#include "rgbmesh/parallel/partition.hpp"

namespace rgbmesh::parallel {

namespace {

bool started = false;
// A communicator of its own for the processes' meeting at a failure (every_process_stops), so
// that it never matches a collective operation that other processes are waiting in.
MPI_Comm failure_comm = MPI_COMM_NULL;

// Rows numbered part after part (each process a contiguous block), in increasing order within
// each part: to_new[old row], to_old[new row], and every part's first row and count.
struct Numbering {
  std::vector<int> to_new, to_old;
  std::vector<int> counts, offsets;
};
Numbering number_by_part(const std::vector<std::int32_t>& part_of, int p) {
  Numbering nb;
  const std::size_t n = part_of.size();
  nb.counts.assign(static_cast<std::size_t>(p), 0);
  nb.offsets.assign(static_cast<std::size_t>(p), 0);
  for (const std::int32_t q : part_of) ++nb.counts[static_cast<std::size_t>(q)];
  for (int q = 1; q < p; ++q)
    nb.offsets[static_cast<std::size_t>(q)] = nb.offsets[static_cast<std::size_t>(q - 1)] + nb.counts[static_cast<std::size_t>(q - 1)];
  nb.to_new.resize(n);
  nb.to_old.resize(n);
  std::vector<int> next = nb.offsets;
  for (std::size_t i = 0; i < n; ++i) {
    const int k = next[static_cast<std::size_t>(part_of[i])]++;
    nb.to_new[i] = k;
    nb.to_old[static_cast<std::size_t>(k)] = static_cast<int>(i);
  }
  return nb;
}

fem::LinearSolution solve(const fem::SparseMatrix& a, const Eigen::VectorXd& b, const Eigen::VectorXd* guess,
                          double tolerance) {
  if (!started) throw std::logic_error("distributed amg: parallel::initialize was not called");
  const int p = processes(), r = rank();
  const auto n = static_cast<std::size_t>(a.rows());
  // Each process's rows: a METIS part of the matrix's graph (the same on every process),
  // numbered part after part so that each process holds a contiguous block.
  const Numbering nb = number_by_part(partition_rows(a, p).part_of, p);
  const std::vector<int>&counts = nb.counts, &offsets = nb.offsets;
  const std::vector<int>&to_new = nb.to_new, &to_old = nb.to_old;
  const int first = offsets[static_cast<std::size_t>(r)], m = counts[static_cast<std::size_t>(r)];
  // The matrix is symmetric: Eigen's columns are its rows. This process's rows, in the new
  // numbering (local rows, global columns).
  std::vector<int> rows(static_cast<std::size_t>(m) + 1, 0), columns;
  std::vector<double> values;
  const int* outer = a.outerIndexPtr();
  for (int k = 0; k < m; ++k) {
    const int i = to_old[static_cast<std::size_t>(first + k)];
    for (int e = outer[i]; e < outer[i + 1]; ++e) {
      columns.push_back(to_new[static_cast<std::size_t>(a.innerIndexPtr()[e])]);
      values.push_back(a.valuePtr()[e]);
    }
    rows[static_cast<std::size_t>(k) + 1] = static_cast<int>(columns.size());
  }
  Eigen::VectorXd rhs(static_cast<Eigen::Index>(n)), x(static_cast<Eigen::Index>(n));
  const bool with_guess = guess != nullptr && guess->size() == b.size() && guess->any();
  for (std::size_t i = 0; i < n; ++i) {
    rhs[to_new[i]] = b[static_cast<Eigen::Index>(i)];
    x[to_new[i]] = with_guess ? (*guess)[static_cast<Eigen::Index>(i)] : 0.0;
  }
  fem::petsc::System s = fem::petsc::compressed_rows(m, static_cast<int>(n), rows.data(), columns.data(), values.data(),
                                                     rhs.data() + first, x.data() + first, tolerance);
  s.distributed = true;
  s.nonzero_guess = with_guess;
  s.solver = "distributed amg";
  fem::LinearSolution out;
  out.iterations = fem::petsc::module().solve(s).iterations;
  // Every process gets the whole solution: the blocks, gathered in rank order, then numbered
  // as the caller's unknowns.
  MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, x.data(), counts.data(), offsets.data(), MPI_DOUBLE,
                 MPI_COMM_WORLD);
  out.x.resize(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) out.x[static_cast<Eigen::Index>(i)] = x[to_new[i]];
  return out;
}

// The system's pieces sent to the processes owning their rows: (row, column, value) with the
// new numbers, column -1 for the right-hand side.
struct Entries {
  std::vector<int> index;  // row, column pairs
  std::vector<double> value;
  void add(int row, int column, double v) {
    index.push_back(row);
    index.push_back(column);
    value.push_back(v);
  }
};

// Sends every process the entries of its rows; returns this process's, its own first and then
// the others' in rank order.
Entries exchange(std::vector<Entries>& outgoing, int me) {
  const int p = static_cast<int>(outgoing.size());
  std::vector<int> send(static_cast<std::size_t>(p)), receive(static_cast<std::size_t>(p));
  for (int q = 0; q < p; ++q) send[static_cast<std::size_t>(q)] = q == me ? 0 : static_cast<int>(outgoing[static_cast<std::size_t>(q)].value.size());
  MPI_Alltoall(send.data(), 1, MPI_INT, receive.data(), 1, MPI_INT, MPI_COMM_WORLD);
  const auto displacements = [p](const std::vector<int>& counts, int width) {
    std::vector<int> d(static_cast<std::size_t>(p), 0);
    for (int q = 1; q < p; ++q) d[static_cast<std::size_t>(q)] = d[static_cast<std::size_t>(q - 1)] + width * counts[static_cast<std::size_t>(q - 1)];
    return d;
  };
  std::vector<int> send2(send), receive2(receive);
  for (int& c : send2) c *= 2;
  for (int& c : receive2) c *= 2;
  const std::vector<int> sd = displacements(send, 1), rd = displacements(receive, 1);
  const std::vector<int> sd2 = displacements(send, 2), rd2 = displacements(receive, 2);
  std::vector<int> index_out, index_in(static_cast<std::size_t>(rd2.back() + receive2.back()));
  std::vector<double> value_out, value_in(static_cast<std::size_t>(rd.back() + receive.back()));
  for (int q = 0; q < p; ++q) {
    if (q == me) continue;
    const Entries& e = outgoing[static_cast<std::size_t>(q)];
    index_out.insert(index_out.end(), e.index.begin(), e.index.end());
    value_out.insert(value_out.end(), e.value.begin(), e.value.end());
  }
  MPI_Alltoallv(index_out.data(), send2.data(), sd2.data(), MPI_INT, index_in.data(), receive2.data(), rd2.data(),
                MPI_INT, MPI_COMM_WORLD);
  MPI_Alltoallv(value_out.data(), send.data(), sd.data(), MPI_DOUBLE, value_in.data(), receive.data(), rd.data(),
                MPI_DOUBLE, MPI_COMM_WORLD);
  Entries mine = std::move(outgoing[static_cast<std::size_t>(me)]);
  mine.index.insert(mine.index.end(), index_in.begin(), index_in.end());
  mine.value.insert(mine.value.end(), value_in.begin(), value_in.end());
  return mine;
}

fem::LinearSolution solve_shared(const fem::SparseMatrix& a, const Eigen::VectorXd& b,
                                 const std::vector<std::int32_t>& row_part, const std::vector<Eigen::Index>&,
                                 const Eigen::VectorXd* guess,
                                 double tolerance) {
  if (!started) throw std::logic_error("shared amg: parallel::initialize was not called");
  const int p = processes(), r = rank();
  const auto n = static_cast<std::size_t>(a.rows());
  const Numbering nb = number_by_part(row_part, p);
  const int first = nb.offsets[static_cast<std::size_t>(r)], m = nb.counts[static_cast<std::size_t>(r)];
  // This process's contributions, to the owners of their rows (the matrix is symmetric:
  // Eigen's column k is row k).
  std::vector<Entries> outgoing(static_cast<std::size_t>(p));
  for (Eigen::Index k = 0; k < a.outerSize(); ++k) {
    Entries& to = outgoing[static_cast<std::size_t>(row_part[static_cast<std::size_t>(k)])];
    const int row = nb.to_new[static_cast<std::size_t>(k)];
    for (fem::SparseMatrix::InnerIterator it(a, k); it; ++it)
      if (it.value() != 0.0) to.add(row, nb.to_new[static_cast<std::size_t>(it.index())], it.value());
    if (b[k] != 0.0) to.add(row, -1, b[k]);
  }
  const Entries mine = exchange(outgoing, r);
  std::vector<Entries>().swap(outgoing);
  // This process's rows: the sums of every process's contributions (added in the order
  // received), in compressed rows with sorted columns.
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(mine.value.size());
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
  for (std::size_t e = 0; e < mine.value.size(); ++e) {
    const int row = mine.index[2 * e] - first, column = mine.index[2 * e + 1];
    if (column < 0) {
      rhs[row] += mine.value[e];
    } else {
      entries.emplace_back(row, column, mine.value[e]);
    }
  }
  Eigen::SparseMatrix<double, Eigen::RowMajor, int> rows(m, static_cast<int>(n));
  rows.setFromTriplets(entries.begin(), entries.end());
  rows.makeCompressed();
  std::vector<Eigen::Triplet<double, int>>().swap(entries);
  Eigen::VectorXd x(m);
  const bool with_guess = guess != nullptr && guess->size() == b.size() && guess->any();
  for (int k = 0; k < m; ++k) x[k] = with_guess ? (*guess)[nb.to_old[static_cast<std::size_t>(first + k)]] : 0.0;
  fem::petsc::System s = fem::petsc::compressed_rows(m, static_cast<int>(n), rows.outerIndexPtr(), rows.innerIndexPtr(),
                                                     rows.valuePtr(), rhs.data(), x.data(), tolerance);
  s.distributed = true;
  s.nonzero_guess = with_guess;
  s.measure_residual = true;  // the residual of the summed system, computed anew
  s.solver = "shared amg";
  const fem::petsc::Result result = fem::petsc::module().solve(s);
  fem::LinearSolution out;
  out.iterations = result.iterations;
  out.relative_residual = result.relative_residual;
  // Every process gets the whole solution: the blocks, gathered in rank order, then numbered
  // as the caller's unknowns.
  Eigen::VectorXd all(static_cast<Eigen::Index>(n));
  MPI_Allgatherv(x.data(), static_cast<int>(m), MPI_DOUBLE, all.data(), nb.counts.data(), nb.offsets.data(), MPI_DOUBLE,
                 MPI_COMM_WORLD);
  out.x.resize(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) out.x[static_cast<Eigen::Index>(i)] = all[nb.to_new[i]];
  return out;
}

}  // namespace

bool mpi_available() { return true; }

bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}

void initialize(int* argc, char*** argv) {
  if (started) return;
  int done = 0;
  MPI_Initialized(&done);
  if (!done) {
    int provided = 0;
    MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  }
  // PETSc (the solver module) on MPI_COMM_WORLD: loaded and initialized now, on every process,
  // since its initialization is collective. Finalized at exit before MPI (below).
  fem::petsc::module();
  started = true;
  MPI_Comm_dup(MPI_COMM_WORLD, &failure_comm);
  // The processes on this machine share its cores: each takes its share for its loops.
  MPI_Comm local = MPI_COMM_NULL;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &local);
  int here = 1;
  MPI_Comm_size(local, &here);
  MPI_Comm_free(&local);
  // (A launcher that bound the process to fewer cores: hardware_threads takes those.)
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  rgbmesh::detail::thread_cap = std::max(1u, cores / static_cast<unsigned>(std::max(1, here)));
  std::atexit([] {
    fem::petsc::module().finalize();
    int mpi_finalized = 0;
    MPI_Finalized(&mpi_finalized);
    if (!mpi_finalized) MPI_Finalize();
  });
}

bool every_process_stops(double seconds) {
  if (!started || processes() == 1) return true;
  MPI_Request request = MPI_REQUEST_NULL;
  MPI_Ibarrier(failure_comm, &request);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  for (;;) {
    int done = 0;
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) return true;
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

void abort_all(int code) {
  if (started) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

int rank() {
  if (!started) return 0;
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int processes() {
  if (!started) return 1;
  int p = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &p);
  return p;
}

fem::LinearSolver distributed_amg() { return solve; }

fem::SharedLinearSolver shared_amg() { return solve_shared; }

void sum(double* values, std::size_t count) {
  // In slices that an int counts.
  constexpr std::size_t kSlice = std::size_t{1} << 30;
  for (std::size_t first = 0; first < count; first += kSlice) {
    const auto n = static_cast<int>(std::min(kSlice, count - first));
    MPI_Allreduce(MPI_IN_PLACE, values + first, n, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  }
}

void gather(double* values, std::size_t width, const std::vector<std::int32_t>& part) {
  const int p = processes(), r = rank();
  std::vector<int> counts(static_cast<std::size_t>(p), 0), offsets(static_cast<std::size_t>(p), 0);
  for (const std::int32_t q : part) counts[static_cast<std::size_t>(q)] += static_cast<int>(width);
  for (int q = 1; q < p; ++q) offsets[static_cast<std::size_t>(q)] = offsets[static_cast<std::size_t>(q - 1)] + counts[static_cast<std::size_t>(q - 1)];
  // Every process's elements in element order, its block after the lower ranks' blocks.
  std::vector<double> all(part.size() * width);
  std::vector<int> next = offsets;
  for (std::size_t e = 0; e < part.size(); ++e) {
    if (part[e] != r) continue;
    std::copy(values + e * width, values + (e + 1) * width, all.begin() + next[static_cast<std::size_t>(r)]);
    next[static_cast<std::size_t>(r)] += static_cast<int>(width);
  }
  MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, all.data(), counts.data(), offsets.data(), MPI_DOUBLE,
                 MPI_COMM_WORLD);
  next = offsets;
  for (std::size_t e = 0; e < part.size(); ++e) {
    const auto q = static_cast<std::size_t>(part[e]);
    std::copy(all.begin() + next[q], all.begin() + next[q] + static_cast<std::ptrdiff_t>(width), values + e * width);
    next[q] += static_cast<int>(width);
  }
}

std::array<std::uint64_t, 2> bytes_sent_since_last() {
  static std::uint64_t before = 0;
  const std::uint64_t now = bytes_sent();
  const unsigned long long mine = now - before;
  unsigned long long total = 0, largest = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  MPI_Allreduce(&mine, &largest, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, MPI_COMM_WORLD);
  before = bytes_sent();  // these two reductions belong to the next interval
  return {total, largest};
}

}  // namespace rgbmesh::parallel
