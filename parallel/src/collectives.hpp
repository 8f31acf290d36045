#pragma once
// Collective operations among the processes of an MPI run, for the distributed mesh
// (distributed_mesh.cpp, which is written against these and no MPI of its own). With MPI in
// mpi_petsc.cpp; without it (mpi_unavailable.cpp) one process: sums and gathers return the
// caller's own values.

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace rgbmesh::parallel::detail {

void sum(std::uint64_t* values, std::size_t count);
/// Every process's vector, concatenated in rank order.
std::vector<std::uint64_t> all_gather(const std::vector<std::uint64_t>& mine);
/// Sends to[q] to process q (to[rank()] stays here); returns what each process sent to this
/// one, by rank.
std::vector<std::vector<std::uint64_t>> all_to_all(const std::vector<std::vector<std::uint64_t>>& to);
std::vector<std::vector<double>> all_to_all(const std::vector<std::vector<double>>& to);
/// How many all_gather and all_to_all calls this process has made: each costs a message to and
/// from every other process whatever it carries, so their number per cycle is what grows with
/// the processes beside the bytes (CycleReport::exchanges).
std::uint64_t exchanges();

/// Entries of a global system for the process owning their rows: (row, column, value), column
/// -1 for the right-hand side.
struct RowEntries {
  std::vector<std::int64_t> index;  // row, column pairs
  std::vector<double> value;
  void add(std::int64_t row, std::int64_t column, double v) {
    index.push_back(row);
    index.push_back(column);
    value.push_back(v);
  }
};
struct OwnedRows {
  Eigen::VectorXd x;  // this process's rows of the solution
  int iterations = 0;
  double relative_residual = 0;
};
/// The symmetric system of `total` rows whose entries each process sends to the rows' owners
/// (to[q]: process q's); this process owns rows [first, first + count). Summed in rank order,
/// solved by CG with BoomerAMG on all processes (guess: this process's rows, or null).
OwnedRows solve_rows(std::vector<RowEntries>& to, std::int64_t first, std::int64_t count, std::int64_t total,
                     const Eigen::VectorXd* guess, double tolerance);

}  // namespace rgbmesh::parallel::detail
