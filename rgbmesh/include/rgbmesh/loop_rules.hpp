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

#include <cmath>

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

/// g^k; exact for the regular 1/4.
inline double eigenvalue_power(double g, int k) {
  if (g == 0.25) return std::ldexp(1.0, -2 * k);
  double r = 1.0;
  for (int i = 0; i < k; ++i) r *= g;
  return r;
}

}  // namespace rgbmesh::loop
