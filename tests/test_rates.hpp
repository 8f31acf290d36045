#pragma once
// Observed convergence rates.

#include <cmath>
#include <vector>

namespace rgbmesh::testing {

// The least-squares slope of log(y) against log(x): the rate in y ~ x^rate.
inline double log_log_slope(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace rgbmesh::testing
