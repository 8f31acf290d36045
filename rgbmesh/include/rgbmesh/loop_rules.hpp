#pragma once
/// \file
/// The weights of Loop subdivision (paper section III-B) and of its multi-step form (section
/// VI-A and the Appendix), for a vertex of valence n.
///
/// \verbatim
/// One step, interior vertex:  p' = (1 - n a_n) p + a_n sum p_i,
///   a_n = (5/8 - (3/8 + 1/4 cos(2 pi / n))^2) / n                        (Eq. 3, 4; a_6 = 1/16)
/// Limit, interior:           p_inf = (1 - n b_n) p + b_n sum p_i,  b_n = 8 a_n / (3 + 8 n a_n)   (Eq. 6)
/// k steps from insertion:    p^{l+k} = g^k p^l + (1 - g^k) p_inf,  g = 5/8 - n a_n  (Eq. 7)
/// Boundary (crease) vertex, with its two boundary neighbours:
///   p' = 3/4 p + 1/8 (p0 + p1),  p_inf = 2/3 p + 1/6 (p0 + p1),  g = 1/4         (Eq. 5, 8, 9)
/// \endverbatim
///
/// g is the subdominant eigenvalue of the local subdivision matrix: the part of p^l that is
/// not yet at the limit shrinks by g per level. It is 1/4 for every regular interior vertex
/// and every boundary vertex; only extraordinary vertices of the base mesh differ.
///
/// Sharp features (sharpness.hpp) follow OpenSubdiv's rules for Loop (Sdc::Crease and
/// its Loop scheme), which RgbMesh, the uniform split and the tests' reference all
/// take from here:
/// \code{.unparsed}
/// Vertex rule at a level: corner if the vertex is sharp or has 3+ sharp edges, else smooth,
///   dart or crease for 0, 1 or 2 sharp edges (boundary edges are infinitely sharp).
/// Even (vertex) masks: smooth and dart as above; crease p' = 3/4 p + 1/8 (a + b), a and b the
///   far ends of the two sharp edges; corner p' = p. Where the rule changes from one level to
///   the next (a semi-sharp value decays to 0) and the parent's is crease or corner, the mask
///   is w parent's + (1 - w) child's, w = transition_weight.
/// Odd (edge) masks: sharpness 0: 3/8, 1/8; a sharp edge whose new vertex is a crease: the
///   midpoint; otherwise a blend with weight s of the midpoint (odd_mask).
/// Sharpness per level: uniform method s - 1; Chaikin 3/4 s + 1/4 (mean of the other
///   semi-sharp edges at that end) - 1 (child_sharpness); 0 and infinite stay.
/// Limits: crease 2/3 p + 1/6 (a + b) for every valence (the crease is a uniform cubic
///   B-spline, so the boundary rules above hold: g = 1/4); corner p (g = 0).
/// \endcode
/// Sharpness is single precision, computed with the same float operations as OpenSubdiv's, so
/// that both make the same decisions and blends.

#include <cmath>

#include "rgbmesh/sharpness.hpp"

namespace rgbmesh::loop {

constexpr double kPi = 3.14159265358979323846;

/// a_n of Eq. 4: the weight of each neighbour in one step of the even rule.
inline double even_neighbor_weight(int n) {
  if (n == 6) return 1.0 / 16.0;
  const double c = 3.0 / 8.0 + 0.25 * std::cos(2.0 * kPi / n);
  return (5.0 / 8.0 - c * c) / n;
}

/// b_n of Eq. 6: the weight of each neighbour in the limit position (1/12 when n = 6).
inline double limit_neighbor_weight(int n) {
  if (n == 6) return 1.0 / 12.0;
  const double a = even_neighbor_weight(n);
  return 8.0 * a / (3.0 + 8.0 * n * a);
}

/// g of Eq. 7 (1/4 when n = 6).
inline double subdominant_eigenvalue(int n) {
  if (n == 6) return 0.25;
  return 5.0 / 8.0 - n * even_neighbor_weight(n);
}

inline constexpr double kBoundaryLimitSelf = 2.0 / 3.0;
inline constexpr double kBoundaryLimitNeighbor = 1.0 / 6.0;
inline constexpr double kBoundaryEigenvalue = 0.25;

inline constexpr double kCreaseEvenSelf = 0.75;
inline constexpr double kCreaseEvenNeighbor = 0.125;

/// g^k; exact for the regular 1/4.
inline double eigenvalue_power(double g, int k) {
  if (g == 0.25) return std::ldexp(1.0, -2 * k);
  double r = 1.0;
  for (int i = 0; i < k; ++i) r *= g;
  return r;
}

// ---- sharp features ----------------------------------------------------------------------

inline bool is_sharp(float s) { return s > 0.0f; }
inline bool is_infinitely_sharp(float s) { return s >= kInfiniteSharpness; }
inline bool is_semi_sharp(float s) { return s > 0.0f && s < kInfiniteSharpness; }

/// One level of the uniform method (and of every vertex sharpness): semi-sharp values lose 1,
/// down to 0; 0 and infinite stay.
inline float decrement_sharpness(float s) {
  if (s <= 0.0f) return 0.0f;
  if (s >= kInfiniteSharpness) return kInfiniteSharpness;
  return s > 1.0f ? s - 1.0f : 0.0f;
}

/// The sharpness of the child at vertex v of an edge of sharpness s, `around` being the
/// sharpness of the edges at v (s's own among them; smooth and infinite ones may be left out,
/// they do not count). Float operations in OpenSubdiv's order: the sum, less s, over the
/// count less one.
inline float child_sharpness(CreaseMethod method, float s, const float* around, int n) {
  if (method == CreaseMethod::uniform) return decrement_sharpness(s);
  if (s <= 0.0f) return 0.0f;
  if (s >= kInfiniteSharpness) return kInfiniteSharpness;
  float sum = 0.0f;
  int count = 0;
  for (int i = 0; i < n; ++i) {
    if (is_semi_sharp(around[i])) {
      ++count;
      sum += around[i];
    }
  }
  if (count > 1) {
    const float others = (sum - s) / static_cast<float>(count - 1);
    s = 0.75f * s + 0.25f * others;
  }
  s -= 1.0f;
  return s > 0.0f ? s : 0.0f;
}

/// The rule of a vertex of that sharpness with that many sharp edges (boundary edges included).
inline VertexRule vertex_rule(float vertex_sharpness, int sharp_edges) {
  if (is_sharp(vertex_sharpness) || sharp_edges > 2) return VertexRule::corner;
  return sharp_edges == 0 ? VertexRule::smooth : (sharp_edges == 1 ? VertexRule::dart : VertexRule::crease);
}

/// The parent rule's weight where a vertex's rule changes between levels: the mean parent
/// sharpness of what decays to 0 (the vertex itself, and its edges: uniform, those of
/// sharpness at most 1; Chaikin, those whose child is 0), at most 1.
inline float transition_weight(CreaseMethod method, float parent_vertex, float child_vertex, int n,
                               const float* parent_edges, const float* child_edges) {
  int count = 0;
  float sum = 0.0f;
  if (is_sharp(parent_vertex) && !is_sharp(child_vertex)) {
    count = 1;
    sum = parent_vertex;
  }
  for (int i = 0; i < n; ++i) {
    const bool decays = method == CreaseMethod::uniform ? parent_edges[i] <= 1.0f : !is_sharp(child_edges[i]);
    if (is_sharp(parent_edges[i]) && decays) {
      sum += parent_edges[i];
      ++count;
    }
  }
  if (count == 0) return 0.0f;
  const float w = sum / static_cast<float>(count);
  return w > 1.0f ? 1.0f : w;
}

/// Weights of the odd (edge) rule: p = end (v0 + v1) + opposite (v2 + v3).
struct OddMask {
  double end = 0.375;
  double opposite = 0.125;
};

/// The odd rule of an edge of sharpness s whose new vertex has the rule crease or not (its two
/// child edges both sharp). A sharp edge whose new vertex is not a crease blends the midpoint
/// and the smooth rule with weight s, as OpenSubdiv does (unclamped: with Chaikin's rule an
/// edge sharper than 1 may have a smooth child).
inline OddMask odd_mask(float s, bool child_is_crease) {
  if (s <= 0.0f) return {};
  if (child_is_crease) return {0.5, 0.0};
  const double p = s;
  const double c = 1.0 - p;
  return {p * 0.5 + c * 0.375, c * 0.125};
}

}  // namespace rgbmesh::loop
