// The collective operations of the distributed mesh over MPI, and its system's solve with
// fem's PETSc module (collectives.hpp).

#include <mpi.h>

#include <Eigen/SparseCore>

#include <limits>
#include <numeric>
#include <stdexcept>

#include "collectives.hpp"
#include "rgbmesh/fem/petsc_module.hpp"
#include "rgbmesh/parallel/mpi.hpp"

namespace rgbmesh::parallel::detail {

namespace {

std::uint64_t exchanges_made = 0;

std::vector<int> displacements(const std::vector<int>& counts) {
  std::vector<int> d(counts.size(), 0);
  for (std::size_t q = 1; q < counts.size(); ++q) d[q] = d[q - 1] + counts[q - 1];
  return d;
}

int as_count(std::size_t n) {
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::runtime_error("distributed mesh: a message of more than 2^31 numbers");
  return static_cast<int>(n);
}

template <class T>
std::vector<std::vector<T>> exchange(const std::vector<std::vector<T>>& to, MPI_Datatype type) {
  const int p = processes();
  if (static_cast<int>(to.size()) != p) throw std::logic_error("all_to_all: one vector per process is needed");
  ++exchanges_made;
  std::vector<int> send(static_cast<std::size_t>(p)), receive(static_cast<std::size_t>(p));
  std::vector<T> out;
  for (int q = 0; q < p; ++q) {
    send[static_cast<std::size_t>(q)] = as_count(to[static_cast<std::size_t>(q)].size());
    out.insert(out.end(), to[static_cast<std::size_t>(q)].begin(), to[static_cast<std::size_t>(q)].end());
  }
  MPI_Alltoall(send.data(), 1, MPI_INT, receive.data(), 1, MPI_INT, MPI_COMM_WORLD);
  const std::vector<int> sd = displacements(send), rd = displacements(receive);
  std::vector<T> in(static_cast<std::size_t>(rd.back() + receive.back()));
  MPI_Alltoallv(out.data(), send.data(), sd.data(), type, in.data(), receive.data(), rd.data(), type, MPI_COMM_WORLD);
  std::vector<std::vector<T>> from(static_cast<std::size_t>(p));
  for (int q = 0; q < p; ++q)
    from[static_cast<std::size_t>(q)].assign(in.begin() + rd[static_cast<std::size_t>(q)],
                                             in.begin() + rd[static_cast<std::size_t>(q)] + receive[static_cast<std::size_t>(q)]);
  return from;
}

}  // namespace

void sum(std::uint64_t* values, std::size_t count) {
  MPI_Allreduce(MPI_IN_PLACE, values, as_count(count), MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
}

std::uint64_t exchanges() { return exchanges_made; }

std::vector<std::uint64_t> all_gather(const std::vector<std::uint64_t>& mine) {
  const int p = processes();
  ++exchanges_made;
  std::vector<int> counts(static_cast<std::size_t>(p));
  const int count = as_count(mine.size());
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  const std::vector<int> offsets = displacements(counts);
  std::vector<std::uint64_t> all(static_cast<std::size_t>(offsets.back() + counts.back()));
  MPI_Allgatherv(mine.data(), count, MPI_UINT64_T, all.data(), counts.data(), offsets.data(), MPI_UINT64_T,
                 MPI_COMM_WORLD);
  return all;
}

std::vector<std::vector<std::uint64_t>> all_to_all(const std::vector<std::vector<std::uint64_t>>& to) {
  return exchange(to, MPI_UINT64_T);
}

std::vector<std::vector<double>> all_to_all(const std::vector<std::vector<double>>& to) { return exchange(to, MPI_DOUBLE); }

OwnedRows solve_rows(std::vector<RowEntries>& to, std::int64_t first, std::int64_t count, std::int64_t total,
                     const Eigen::VectorXd* guess, double tolerance) {
  const int p = processes(), me = rank();
  // The entries are a solve's largest transient: this process's own rows (most of them) go
  // straight to the triplets, only the others' travel, and each buffer is freed once copied.
  std::vector<int> send(static_cast<std::size_t>(p), 0), receive(static_cast<std::size_t>(p));
  std::size_t entries_out = 0;
  for (int q = 0; q < p; ++q)
    if (q != me) {
      send[static_cast<std::size_t>(q)] = as_count(to[static_cast<std::size_t>(q)].value.size());
      entries_out += to[static_cast<std::size_t>(q)].value.size();
    }
  std::vector<std::int64_t> index_out;
  std::vector<double> value_out;
  index_out.reserve(2 * entries_out);
  value_out.reserve(entries_out);
  for (int q = 0; q < p; ++q) {
    if (q == me) continue;
    RowEntries& e = to[static_cast<std::size_t>(q)];
    index_out.insert(index_out.end(), e.index.begin(), e.index.end());
    value_out.insert(value_out.end(), e.value.begin(), e.value.end());
    e = {};
  }
  MPI_Alltoall(send.data(), 1, MPI_INT, receive.data(), 1, MPI_INT, MPI_COMM_WORLD);
  std::vector<int> send2(send), receive2(receive);
  for (int& c : send2) c = as_count(2 * static_cast<std::size_t>(c));
  for (int& c : receive2) c = as_count(2 * static_cast<std::size_t>(c));
  const std::vector<int> sd = displacements(send), rd = displacements(receive), sd2 = displacements(send2),
                         rd2 = displacements(receive2);
  std::vector<std::int64_t> index_in(static_cast<std::size_t>(rd2.back() + receive2.back()));
  MPI_Alltoallv(index_out.data(), send2.data(), sd2.data(), MPI_INT64_T, index_in.data(), receive2.data(), rd2.data(),
                MPI_INT64_T, MPI_COMM_WORLD);
  std::vector<std::int64_t>().swap(index_out);
  std::vector<double> value_in(static_cast<std::size_t>(rd.back() + receive.back()));
  MPI_Alltoallv(value_out.data(), send.data(), sd.data(), MPI_DOUBLE, value_in.data(), receive.data(), rd.data(),
                MPI_DOUBLE, MPI_COMM_WORLD);
  std::vector<double>().swap(value_out);
  // This process's rows: its own contributions, then the others' in rank order.
  RowEntries& own = to[static_cast<std::size_t>(me)];
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(own.value.size() + value_in.size());
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(count);
  const auto add = [&](std::int64_t row, std::int64_t column, double value) {
    row -= first;
    if (row < 0 || row >= count) throw std::logic_error("distributed mesh: an entry for a row of another process");
    if (column < 0) {
      rhs[row] += value;
    } else {
      entries.emplace_back(static_cast<int>(row), static_cast<int>(column), value);
    }
  };
  for (std::size_t e = 0; e < own.value.size(); ++e) add(own.index[2 * e], own.index[2 * e + 1], own.value[e]);
  own = {};
  for (std::size_t e = 0; e < value_in.size(); ++e) add(index_in[2 * e], index_in[2 * e + 1], value_in[e]);
  std::vector<std::int64_t>().swap(index_in);
  std::vector<double>().swap(value_in);
  Eigen::SparseMatrix<double, Eigen::RowMajor, int> rows(static_cast<int>(count), static_cast<int>(total));
  rows.setFromTriplets(entries.begin(), entries.end());
  rows.makeCompressed();
  std::vector<Eigen::Triplet<double, int>>().swap(entries);
  OwnedRows out;
  out.x = Eigen::VectorXd::Zero(count);
  int any_guess = guess != nullptr && guess->size() == count && guess->any() ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &any_guess, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  if (guess != nullptr && guess->size() == count) out.x = *guess;
  using Rows = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
  fem::petsc::System system =
      fem::petsc::compressed_rows(static_cast<int>(count), static_cast<int>(total), rows.outerIndexPtr(),
                                  rows.innerIndexPtr(), rows.valuePtr(), rhs.data(), out.x.data(), tolerance);
  system.distributed = true;
  system.nonzero_guess = any_guess != 0;
  system.measure_residual = true;
  system.solver = "distributed mesh amg";
  // PETSc copied the arrays: free them before the AMG setup, the solve's peak of memory.
  system.matrix_copied = [](void* context) { Rows().swap(*static_cast<Rows*>(context)); };
  system.context = &rows;
  const fem::petsc::Result result = fem::petsc::module().solve(system);
  out.iterations = result.iterations;
  out.relative_residual = result.relative_residual;
  return out;
}

}  // namespace rgbmesh::parallel::detail
