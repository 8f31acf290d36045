#pragma once
// `rgbmesh fit`: Loop subdivision surfaces fitted to scanned points (rgbmesh::fit).

#include <cstddef>
#include <string>

namespace rgbmesh::cli {

struct FitArgs {
  std::string target;
  std::string base;            // empty: decimate the target mesh to base_faces
  std::size_t base_faces = 1000;
  int levels = 3;
  std::string loss = "huber";  // huber, cauchy, none
  double smooth = 1e-3;
  int iterations = 30;
  std::string out = "out";
  std::string report;
};

// Runs the fit and writes DIR/fitted_base.obj, DIR/limit_surface.vtp (point data "distance":
// to the nearest target), DIR/initial_limit_surface.vtp (the starting base's limit surface)
// and the report; returns the exit code. InputError on bad input.
int run_fit(const FitArgs& args);

}  // namespace rgbmesh::cli
