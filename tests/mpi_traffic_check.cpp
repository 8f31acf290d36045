// The bytes an MPI run sends (rgbmesh::parallel::bytes_sent, counted through MPI's profiling
// interface), run by CTest under mpirun on two processes: a point-to-point message counts its
// payload exactly on the sender and nothing on the receiver; parallel::sum counts each
// process's contribution; a distributed solve counts more than rgbmesh's own gather of the
// solution, so the messages that PETSc and hypre send from their shared libraries are counted
// too; the per-cycle figures add up over the processes. Exit 0 when all hold.

#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "rgbmesh/parallel/mpi.hpp"

namespace {

int failures = 0;

void expect(bool ok, const std::string& what) {
  if (ok) return;
  ++failures;
  std::fprintf(stderr, "rank %d: FAILED: %s\n", rgbmesh::parallel::rank(), what.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  namespace par = rgbmesh::parallel;
  par::initialize(&argc, &argv);
  const int r = par::rank(), p = par::processes();
  expect(p == 2, "run on two processes (got " + std::to_string(p) + ")");
  if (p != 2) return 1;

  // A message of 1,000 doubles from rank 0 to rank 1.
  std::uint64_t before = par::bytes_sent();
  std::vector<double> buffer(1000, 1.0);
  if (r == 0) {
    MPI_Send(buffer.data(), 1000, MPI_DOUBLE, 1, 7, MPI_COMM_WORLD);
  } else {
    MPI_Recv(buffer.data(), 1000, MPI_DOUBLE, 0, 7, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  }
  std::uint64_t delta = par::bytes_sent() - before;
  expect(delta == (r == 0 ? 8000u : 0u), "a point-to-point message: " + std::to_string(delta) + " bytes");

  // A sum over the processes: each contributes its 100 doubles.
  std::vector<double> values(100, r + 1.0);
  before = par::bytes_sent();
  par::sum(values.data(), values.size());
  delta = par::bytes_sent() - before;
  expect(delta == 800, "the sum: " + std::to_string(delta) + " bytes");
  expect(values[0] == 3.0 && values[99] == 3.0, "the sum's values");

  // A distributed solve of the 5-point Laplacian (plus a shift) on a 100 x 100 grid with CG
  // and BoomerAMG. Each process's rows are half the grid: every product with the matrix sends
  // the values along the cut (at least a grid line, 100 numbers) to the other process.
  const int side = 100, n = side * side;
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < side; ++i) {
    for (int j = 0; j < side; ++j) {
      const int k = i * side + j;
      entries.emplace_back(k, k, 4.01);
      if (i > 0) entries.emplace_back(k, k - side, -1.0);
      if (i + 1 < side) entries.emplace_back(k, k + side, -1.0);
      if (j > 0) entries.emplace_back(k, k - 1, -1.0);
      if (j + 1 < side) entries.emplace_back(k, k + 1, -1.0);
    }
  }
  rgbmesh::fem::SparseMatrix a(n, n);
  a.setFromTriplets(entries.begin(), entries.end());
  a.makeCompressed();
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(n);
  before = par::bytes_sent();
  const rgbmesh::fem::LinearSolution x = par::distributed_amg()(a, b, nullptr, 1e-10);
  delta = par::bytes_sent() - before;
  expect((b - a * x.x).norm() <= 1e-8 * b.norm(), "the distributed solve's residual");
  expect(x.iterations >= 3, "the solve's iterations: " + std::to_string(x.iterations));
  // rgbmesh's own messages: the solution, each process's rows gathered by all, n numbers in
  // all. PETSc's products alone send at least a grid line per iteration from each process.
  unsigned long long mine = delta, total = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  const std::uint64_t own = 8u * static_cast<std::uint64_t>(n);
  const std::uint64_t products = 2 * 8u * static_cast<std::uint64_t>(side) * static_cast<std::uint64_t>(x.iterations);
  expect(total >= own + products, "the solve sent " + std::to_string(total) + " bytes, rgbmesh's own gather " +
                                      std::to_string(own) + " and PETSc's products at least " +
                                      std::to_string(products) + ": the libraries' messages are not counted");
  expect(total <= own + 100 * products, "the solve sent " + std::to_string(total) + " bytes: more than can be");

  // The per-cycle figures: all processes' bytes since the last call, and the most by one.
  par::bytes_sent_since_last();
  if (r == 0) MPI_Send(buffer.data(), 500, MPI_DOUBLE, 1, 8, MPI_COMM_WORLD);
  if (r == 1) MPI_Recv(buffer.data(), 500, MPI_DOUBLE, 0, 8, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  const std::array<std::uint64_t, 2> cycle = par::bytes_sent_since_last();
  expect(cycle[0] == 4000 && cycle[1] == 4000,
         "since the last call: " + std::to_string(cycle[0]) + " in all, " + std::to_string(cycle[1]) + " the most");

  int all = 0;
  MPI_Allreduce(&failures, &all, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  if (r == 0) std::printf("%s\n", all == 0 ? "bytes sent: all checks hold" : "bytes sent: checks failed");
  return all == 0 ? 0 : 1;
}
