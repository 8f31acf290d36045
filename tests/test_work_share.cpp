// The estimators and the error norms shared among processes (fem::WorkShare, how an MPI run
// divides them): P "processes" emulated by threads, each computing the terms of its own
// triangles, with a sum across them that adds their vectors in process order. Every process
// must get each η_T bit for bit as one process computes it (P1 and P2, residual and ZZ, with
// Neumann boundaries and on the closed sphere), and the norms within rounding, including the
// zero-mean comparison, whose mean is itself a sum over the processes.

#include <gtest/gtest.h>

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <random>
#include <thread>
#include <utility>
#include <vector>

#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/fem/estimators.hpp"
#include "rgbmesh/fem/problem.hpp"
#include "rgbmesh/fem/solver.hpp"
#include "rgbmesh/refinement.hpp"
#include "test_meshes.hpp"

namespace rgbmesh::fem {
namespace {

// The exchanges among `processes` threads, as among processes: each deposits its values, the
// last to arrive combines them (a sum in process order, or each triangle's values from its
// own process), and all leave with the result.
class ThreadExchange {
 public:
  explicit ThreadExchange(int processes) : deposits_(static_cast<std::size_t>(processes)) {}
  void sum(int process, double* values, std::size_t count) {
    exchange(process, values, count, [&] {
      std::vector<double> out(count, 0.0);
      for (const auto& d : deposits_)
        for (std::size_t i = 0; i < count; ++i) out[i] += d[i];
      return out;
    });
  }
  void gather(int process, double* values, std::size_t width, const std::vector<std::int32_t>& part) {
    exchange(process, values, width * part.size(), [&] {
      std::vector<double> out(width * part.size());
      for (std::size_t t = 0; t < part.size(); ++t)
        for (std::size_t k = 0; k < width; ++k)
          out[t * width + k] = deposits_[static_cast<std::size_t>(part[t])][t * width + k];
      return out;
    });
  }

 private:
  template <class Combine>
  void exchange(int process, double* values, std::size_t count, Combine&& combine) {
    std::unique_lock<std::mutex> lock(mutex_);
    const long round = round_;
    deposits_[static_cast<std::size_t>(process)].assign(values, values + count);
    if (++arrived_ == static_cast<int>(deposits_.size())) {
      result_ = combine();
      arrived_ = 0;
      ++round_;
      changed_.notify_all();
    } else {
      changed_.wait(lock, [&] { return round_ != round; });
    }
    std::copy(result_.begin(), result_.end(), values);
  }
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<std::vector<double>> deposits_;
  std::vector<double> result_;
  int arrived_ = 0;
  long round_ = 0;
};

// Runs work(share) on `processes` threads, triangle t belonging to process part[t].
template <class Result>
std::vector<Result> on_processes(int processes, const std::vector<std::int32_t>& part,
                                 const std::function<Result(const WorkShare&)>& work) {
  ThreadExchange exchange(processes);
  std::vector<Result> out(static_cast<std::size_t>(processes));
  std::vector<std::thread> threads;
  for (int q = 0; q < processes; ++q) {
    threads.emplace_back([&, q] {
      WorkShare share;
      share.part = part;
      share.process = q;
      share.sum = [&exchange, q](double* v, std::size_t n) { exchange.sum(q, v, n); };
      share.gather = [&exchange, q](double* v, std::size_t w, const std::vector<std::int32_t>& p) {
        exchange.gather(q, v, w, p);
      };
      out[static_cast<std::size_t>(q)] = work(share);
    });
  }
  for (std::thread& t : threads) t.join();
  return out;
}

// Parts made of runs of neighbouring triangles (as a partition would give) and stray single
// triangles, so that many edges lie between parts.
std::vector<std::int32_t> parts_of(std::size_t triangles, int processes) {
  std::vector<std::int32_t> part(triangles);
  for (std::size_t t = 0; t < triangles; ++t)
    part[t] = t % 7 == 3 ? static_cast<int>((t / 7) % processes) : static_cast<int>(t * processes / triangles);
  return part;
}

void expect_shared_like_one(const SurfaceMesh& mesh, const Problem& problem, bool exact_solution) {
  const Solution s = solve(mesh, problem);
  const Estimate residual = residual_estimator(mesh, problem, s.u), zz = zz_estimator(mesh, s.u);
  for (int processes : {2, 3}) {
    const std::vector<std::int32_t> part = parts_of(mesh.triangles.size(), processes);
    for (const bool use_zz : {false, true}) {
      const Estimate& one = use_zz ? zz : residual;
      const std::vector<Estimate> many = on_processes<Estimate>(processes, part, [&](const WorkShare& share) {
        return use_zz ? zz_estimator(mesh, s.u, share) : residual_estimator(mesh, problem, s.u, share);
      });
      for (const Estimate& e : many) {
        ASSERT_EQ(e.eta.size(), one.eta.size());
        std::size_t differ = 0;
        for (std::size_t t = 0; t < e.eta.size(); ++t)
          differ += e.eta[t] != one.eta[t] || e.geometric[t] != one.geometric[t];
        EXPECT_EQ(differ, 0u) << processes << " processes, " << (use_zz ? "zz" : "residual") << ", order " << mesh.order;
        EXPECT_EQ(e.total, one.total);
      }
    }
    if (!exact_solution) continue;
    const ErrorNorms one = error_norms(mesh, s.u, *problem.exact, s.zero_mean);
    const std::vector<ErrorNorms> many = on_processes<ErrorNorms>(processes, part, [&](const WorkShare& share) {
      return error_norms(mesh, s.u, *problem.exact, s.zero_mean, share);
    });
    for (const ErrorNorms& e : many) {
      EXPECT_NEAR(e.l2, one.l2, 1e-12 * one.l2) << processes << " processes, order " << mesh.order;
      EXPECT_NEAR(e.h1, one.h1, 1e-12 * one.h1) << processes << " processes, order " << mesh.order;
    }
  }
}

TEST(WorkShare, EstimatesAndNormsOnTheClosedSphereAreThoseOfOneProcess) {
  for (int order : {1, 2}) {
    RgbMesh m = testing::icosahedron().build();
    selective_refinement(m, UniformLevel(3));
    const SurfaceMesh mesh = build_surface_mesh(m, Projection(project_to_unit_sphere), order);
    const Problem p = sphere_peak(Vec3(0.48, 0.6, 0.64), 100.0, 0.0);
    ASSERT_TRUE(solve(mesh, p).zero_mean);  // the mean is compared too
    expect_shared_like_one(mesh, p, true);
  }
}

TEST(WorkShare, NeumannEdgesAndTheLoopSurfaceAreSharedToo) {
  for (int order : {1, 2}) {
    RgbMesh m = testing::fan_disk(6).build();
    selective_refinement(m, UniformLevel(3));
    // On the Loop limit surface (no projection): the geometric term's kinks between elements.
    const SurfaceMesh mesh = build_surface_mesh(m, std::nullopt, order);
    ASSERT_FALSE(mesh.boundary_edges.empty());
    Problem p;
    p.name = "neumann";
    p.c = 1;
    p.source = [](const Vec3& x) { return 1 + x.x * x.y; };
    p.is_neumann = [](const Vec3& x) { return x.x > 0; };
    p.neumann_flux = [](const Vec3& x) { return x.y; };
    expect_shared_like_one(mesh, p, false);
  }
}

// Marking on a distributed mesh (adapt::Indicators with own flags and sums): each process
// passes only its own triangles' indicators; the union of what they mark is what the same
// strategy marks on one process holding all, also
// with ties (equal indicators and ones that only rounding separates) at the threshold.
TEST(WorkShare, MarksFoundTogetherAreTheMarksOfOneProcess) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> value(0.0, 1.0);
  for (int processes : {1, 2, 3, 4}) {
    for (int trial = 0; trial < 4; ++trial) {
      const std::size_t n = 500 + 97 * static_cast<std::size_t>(trial);
      std::vector<double> eta(n);
      for (double& e : eta) e = std::pow(value(rng), 3);
      for (std::size_t i = 0; i < n; i += 7) eta[i] = eta[i / 2];              // exact ties
      for (std::size_t i = 3; i < n; i += 11) eta[i] = eta[i - 1] * (1 + 1e-9);  // rounding apart
      const std::vector<std::int32_t> part = parts_of(n, processes);
      for (const adapt::NamedMarking& named : adapt::marking_table()) {
        for (const double theta : {0.3, 0.5, 0.9}) {
          const auto marking = named.make(theta);
          const double target = 0.5 * std::sqrt(static_cast<double>(n)) * eta[n / 3];
          const std::vector<char> whole = marking->mark(adapt::Indicators(eta, target));
          const double threshold = marking->refinement_threshold(adapt::Indicators(eta, target), whole);
          using Marks = std::pair<std::vector<char>, double>;  // the marks and the refinement threshold
          const auto marks = on_processes<Marks>(processes, part, [&](const WorkShare& share) {
            // Each process holds its own indicators only (the others' are not known to it).
            std::vector<double> mine(n, 0.0);
            std::vector<char> own(n, 0);
            for (std::size_t t = 0; t < n; ++t)
              if (share.computes(t)) {
                mine[t] = eta[t];
                own[t] = 1;
              }
            const adapt::Indicators mine_only(mine, target, own, share.sum);
            std::vector<char> marked = marking->mark(mine_only);
            const double found = marking->refinement_threshold(mine_only, marked);
            return Marks{std::move(marked), found};
          });
          std::vector<char> joined(n, 0);
          for (int q = 0; q < processes; ++q)
            for (std::size_t t = 0; t < n; ++t) {
              if (marks[static_cast<std::size_t>(q)].first[t]) {
                EXPECT_EQ(part[t], q) << "a process marks only its own triangles";
                joined[t] = 1;
              }
            }
          EXPECT_EQ(joined, whole) << processes << " processes, marking " << named.name << ", theta "
                                   << theta;
          EXPECT_GT(std::count(whole.begin(), whole.end(), 1), 0);
          for (const Marks& m : marks)
            EXPECT_EQ(m.second, threshold) << "the whole mesh's refinement threshold";
        }
      }
    }
  }
}

}  // namespace
}  // namespace rgbmesh::fem
