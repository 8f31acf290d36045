// What the Loop elements can tell a user about the surface they run on (see loop_elements.hpp).

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "rgbmesh/fem/loop_elements.hpp"

namespace rgbmesh::fem {

double loop_parametrization_ratio(const LoopSpace& space, std::size_t element) {
  double smallest = 1;
  for (std::size_t p = 0; p < space.elements[element].rule->size(); ++p) {
    const LoopPoint q = loop_point(space, element, p);
    // The eigenvalues of the metric [a b; b c] are the squared singular values of [y_u y_v].
    const double a = dot(q.xu, q.xu), b = dot(q.xu, q.xv), c = dot(q.xv, q.xv);
    const double half_trace = 0.5 * (a + c);
    const double gap = std::sqrt(std::max(half_trace * half_trace - (a * c - b * b), 0.0));
    const double largest = half_trace + gap;
    // det / largest rather than half_trace - gap: no cancellation when the tangents are nearly
    // parallel, which is the case this measures.
    const double least = largest > 0 ? std::max(a * c - b * b, 0.0) / largest : 0.0;
    const double ratio = largest > 0 && std::isfinite(least) ? std::sqrt(least / largest) : 0.0;
    smallest = std::min(smallest, ratio);
  }
  return smallest;
}

LoopSingularEstimate loop_singular_estimate(const LoopSpace& space, const std::vector<double>& eta,
                                            double below) {
  LoopSingularEstimate out;
  double total = 0;
  for (const double e : eta) total += e * e;
  if (!(total > 0) || !std::isfinite(total)) return out;
  std::vector<std::size_t> order(eta.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return eta[i] > eta[j]; });
  // Down the indicators: stop once the regular elements seen carry half (the singular ones
  // cannot be a majority), or at 99% (they are: the share is then measured to 1%).
  double seen = 0, singular = 0;
  for (const std::size_t e : order) {
    if (seen - singular > 0.5 * total || seen >= 0.99 * total) break;
    seen += eta[e] * eta[e];
    const double ratio = loop_parametrization_ratio(space, e);
    if (ratio >= below) continue;
    if (out.elements == 0) out.where = loop_point(space, e, 0).x;
    singular += eta[e] * eta[e];
    out.elements += 1;
    out.ratio = std::min(out.ratio, ratio);
  }
  out.share = singular / total;
  return out;
}

}  // namespace rgbmesh::fem
