#pragma once
/// \file
/// The share of the per-triangle work that falls to this process in a distributed run.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace rgbmesh::fem {

/// How the processes of a distributed run share the per-triangle work of assembly, estimators
/// and norms (rgbmesh::parallel): each computes the terms of its own triangles (and of the
/// edges next to them). The estimators' `gather` then gives every process the others'
/// per-triangle values, and `sum` adds up partial sums (the norms, the mean of a zero-mean
/// problem). The estimates come out bit for bit those of one process (each η_T is computed
/// whole by its process); sums only change order. The default, one process: every triangle
/// here, nothing to exchange.
struct WorkShare {
  std::vector<std::int32_t> part;  ///< per FE triangle: the process computing it (empty: all here)
  std::int32_t process = 0;        ///< this process
  /// Adds values across the processes, in place.
  std::function<void(double* values, std::size_t count)> sum;
  /// values holds `width` numbers per triangle, valid for this process's triangles: fills in
  /// every other triangle's from its process (each process sends only its own).
  std::function<void(double* values, std::size_t width, const std::vector<std::int32_t>& part)> gather;

  bool computes(std::size_t triangle) const { return part.empty() || part[triangle] == process; }
};

}  // namespace rgbmesh::fem
