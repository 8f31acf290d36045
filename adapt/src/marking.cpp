#include "rgbmesh/adapt/marking.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <queue>

#include "rgbmesh/errors.hpp"

namespace rgbmesh::adapt {

namespace {

// Non-negative doubles order as their bit patterns: the bisections below search the bits.
double as_double(std::uint64_t bits) {
  double x = 0;
  std::memcpy(&x, &bits, sizeof x);
  return x;
}
constexpr std::uint64_t kInfinityBits = 0x7FF0000000000000ull;

// The largest indicators, down to the k-th, k the fewest whose weights (η² for Dörfler, 1 for
// the fixed fraction) reach `goal`, plus the ties within a relative 1e-6 of the k-th.
std::vector<char> mark_largest(const Indicators& in, bool bulk, double theta) {
  const std::vector<double>& eta = in.eta;
  std::vector<char> marked(eta.size(), 0);
  if (!in.distributed()) {
    if (eta.empty()) return marked;
    std::vector<std::size_t> order(eta.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&eta](std::size_t a, std::size_t b) { return eta[a] > eta[b]; });
    std::size_t k = 0;
    if (!bulk) {
      const auto n = static_cast<std::size_t>(std::ceil(theta * static_cast<double>(eta.size())));
      for (; k < std::min(n, eta.size()); ++k) marked[order[k]] = 1;
    } else {
      double total = 0;
      for (double e : eta) total += e * e;
      double sum = 0;
      for (; k < order.size() && sum < theta * total; ++k) {
        marked[order[k]] = 1;
        sum += eta[order[k]] * eta[order[k]];
      }
    }
    // Ties: on symmetric meshes many indicators are equal but for rounding, and rounding (the
    // solver's last digits, which differ with the number of processes) must not choose which
    // of them are refined: the same marks, and the same mesh, on any number of processes.
    if (k > 0) {
      const double cutoff = eta[order[k - 1]] * (1 - 1e-6);
      for (; k < order.size() && eta[order[k]] >= cutoff; ++k) marked[order[k]] = 1;
    }
    return marked;
  }
  if (in.own->size() != eta.size())
    throw std::invalid_argument("marking: one own flag per indicator is needed");
  double totals[2] = {0, 0};  // own triangles, Σ η²
  for (std::size_t i = 0; i < eta.size(); ++i)
    if (in.is_own(i)) {
      totals[0] += 1;
      totals[1] += eta[i] * eta[i];
    }
  in.add_over_processes(totals, 2);
  const double n = totals[0];
  if (n == 0) return marked;
  // The one-process marks end at the k-th largest indicator: the largest x for which the
  // indicators at least x reach the goal, found by bisection on x's bits, one sum a step.
  const double goal = bulk ? theta * totals[1] : std::ceil(theta * n);
  if (!(goal > 0)) return marked;
  const auto reaches = [&](double x) {
    double s = 0;
    for (std::size_t i = 0; i < eta.size(); ++i)
      if (in.is_own(i) && eta[i] >= x) s += bulk ? eta[i] * eta[i] : 1.0;
    in.add_over_processes(&s, 1);
    return s >= goal;
  };
  std::uint64_t lo = 0, hi = kInfinityBits;
  if (reaches(as_double(lo))) {
    while (hi - lo > 1) {
      const std::uint64_t mid = lo + (hi - lo) / 2;
      (reaches(as_double(mid)) ? lo : hi) = mid;
    }
  }
  // (Where even every indicator does not reach the goal, all are marked: x = 0.) The ties, as
  // on one process: every indicator within a relative 1e-6 of the k-th.
  const double cutoff = as_double(lo) * (1 - 1e-6);
  for (std::size_t i = 0; i < eta.size(); ++i) marked[i] = in.is_own(i) && eta[i] >= cutoff ? 1 : 0;
  return marked;
}

void require_theta(double theta, const char* strategy) {
  if (!(theta > 0 && theta <= 1))
    throw InputError(std::string(strategy) + ": theta must be in (0, 1], got " + std::to_string(theta));
}

// The number of own triangles over all processes.
double own_count(const Indicators& in) {
  double n = 0;
  for (std::size_t i = 0; i < in.eta.size(); ++i) n += in.is_own(i) ? 1 : 0;
  in.add_over_processes(&n, 1);
  return n;
}

}  // namespace

double MarkingStrategy::refinement_threshold(const Indicators& in, const std::vector<char>& marked) const {
  const std::vector<double>& eta = in.eta;
  if (!in.distributed()) {
    double smallest = 0;
    bool any = false;
    for (std::size_t i = 0; i < eta.size(); ++i) {
      if (!marked[i]) continue;
      smallest = any ? std::min(smallest, eta[i]) : eta[i];
      any = true;
    }
    return smallest;
  }
  // The smallest marked indicator of all processes: the smallest x that at least one marked
  // indicator does not pass, by bisection on x's bits, each step one sum.
  double count = 0;
  for (std::size_t i = 0; i < marked.size(); ++i) count += marked[i] && in.is_own(i) ? 1 : 0;
  in.add_over_processes(&count, 1);
  if (count == 0) return 0;
  const auto some_at_most = [&](double x) {
    double s = 0;
    for (std::size_t i = 0; i < eta.size(); ++i)
      if (marked[i] && in.is_own(i) && eta[i] <= x) s += 1;
    in.add_over_processes(&s, 1);
    return s > 0;
  };
  std::uint64_t lo = 0, hi = kInfinityBits;  // the answer is in (lo, hi]
  if (some_at_most(0.0)) return 0.0;
  while (hi - lo > 1) {
    const std::uint64_t mid = lo + (hi - lo) / 2;
    (some_at_most(as_double(mid)) ? hi : lo) = mid;
  }
  return as_double(hi);
}

DorflerMarking::DorflerMarking(double theta) : theta_(theta) { require_theta(theta, "dorfler marking"); }

std::vector<char> DorflerMarking::mark(const Indicators& in) const { return mark_largest(in, true, theta_); }

FixedFractionMarking::FixedFractionMarking(double theta) : theta_(theta) {
  require_theta(theta, "fixed-fraction marking");
}

std::vector<char> FixedFractionMarking::mark(const Indicators& in) const {
  return mark_largest(in, false, theta_);
}

std::vector<char> EquidistributionMarking::mark(const Indicators& in) const {
  std::vector<char> marked(in.eta.size(), 0);
  const double n = in.distributed() ? own_count(in) : static_cast<double>(in.eta.size());
  if (n == 0) return marked;
  const double limit = in.target_estimate / std::sqrt(n);
  for (std::size_t i = 0; i < in.eta.size(); ++i) marked[i] = in.is_own(i) && in.eta[i] > limit ? 1 : 0;
  return marked;
}

double EquidistributionMarking::refinement_threshold(const Indicators& in, const std::vector<char>&) const {
  const double n = in.distributed() ? own_count(in) : static_cast<double>(in.eta.size());
  return n > 0 ? in.target_estimate / std::sqrt(n) : 0.0;
}

std::shared_ptr<const MarkingStrategy> EquidistributionMarking::before_target() const {
  return std::make_shared<DorflerMarking>(start_theta_);
}

const std::vector<NamedMarking>& marking_table() {
  static const std::vector<NamedMarking> table = {
      {"dorfler", "the fewest triangles carrying the fraction theta of the squared estimate",
       [](double theta) {
         return std::shared_ptr<const MarkingStrategy>(std::make_shared<DorflerMarking>(theta));
       }},
      {"fraction", "the fraction theta of the triangles with the largest indicators",
       [](double theta) {
         return std::shared_ptr<const MarkingStrategy>(std::make_shared<FixedFractionMarking>(theta));
       }},
      {"equidistribution", "every triangle whose indicator exceeds the target / sqrt(number of triangles)",
       [](double theta) {
         return std::shared_ptr<const MarkingStrategy>(std::make_shared<EquidistributionMarking>(theta));
       }},
  };
  return table;
}

std::shared_ptr<const MarkingStrategy> make_marking(const std::string& name, double theta) {
  return named_row(marking_table(), name, "marking").make(theta);
}

std::size_t mark_admissible(const RgbMesh& mesh, const std::vector<TriangleHandle>& triangles,
                            std::vector<char>& marked, int levels) {
  if (marked.size() != triangles.size())
    throw std::invalid_argument("mark_admissible: one mark per triangle");
  if (levels < 2) return 0;
  std::vector<std::int32_t> entry(static_cast<std::size_t>(mesh.triangle_slots()), -1);
  for (std::size_t i = 0; i < triangles.size(); ++i)
    entry[static_cast<std::size_t>(triangles[i].idx)] = static_cast<std::int32_t>(i);
  // The marked triangles by the level k whose cells they make refine, walked from the finest
  // k down: a triangle marked by the walk of level k has level k or less, so it makes level
  // k - 1 or coarser refine, and is walked later. One walk per level, from all its triangles'
  // corners at once (the union of their neighbourhoods).
  std::vector<std::vector<std::size_t>> by_level;
  const auto add = [&](std::size_t i) {
    const int k = mesh.level(triangles[i]) - levels + 1;
    if (k < 0) return;
    if (by_level.size() <= static_cast<std::size_t>(k)) by_level.resize(static_cast<std::size_t>(k) + 1);
    by_level[static_cast<std::size_t>(k)].push_back(i);
  };
  for (std::size_t i = 0; i < marked.size(); ++i)
    if (marked[i]) add(i);
  std::size_t added = 0;
  std::vector<double> distance(static_cast<std::size_t>(mesh.vertex_slots()), -1.0);
  std::vector<std::int32_t> reached;
  using Item = std::pair<double, std::int32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> front;
  VertexStar star;
  constexpr double kReach = 3.0;  // level-k edges
  for (int k = static_cast<int>(by_level.size()) - 1; k >= 0; --k) {
    for (const std::size_t i : by_level[static_cast<std::size_t>(k)])
      for (const VertexHandle v : mesh.triangle_vertices(triangles[i])) front.emplace(0.0, v.idx);
    while (!front.empty()) {
      const auto [d, slot] = front.top();
      front.pop();
      double& known = distance[static_cast<std::size_t>(slot)];
      if (known >= 0 && known <= d) continue;
      if (known < 0) reached.push_back(slot);
      known = d;
      mesh.star(VertexHandle(slot), star);
      for (const TriangleHandle u : star.triangles) {
        const std::int32_t e = entry[static_cast<std::size_t>(u.idx)];
        if (e < 0 || marked[static_cast<std::size_t>(e)] || mesh.level(u) > k) continue;
        marked[static_cast<std::size_t>(e)] = 1;
        add(static_cast<std::size_t>(e));
        ++added;
      }
      for (std::size_t n = 0; n < star.neighbors.size(); ++n) {
        const double step = std::ldexp(1.0, k - mesh.level(star.edges[n]));
        if (d + step <= kReach) front.emplace(d + step, star.neighbors[n].idx);
      }
    }
    for (const std::int32_t slot : reached) distance[static_cast<std::size_t>(slot)] = -1.0;
    reached.clear();
  }
  return added;
}

}  // namespace rgbmesh::adapt
