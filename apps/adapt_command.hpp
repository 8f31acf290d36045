#pragma once
// `rgbmesh adapt`: error-driven adaptive cycles written for ParaView. It is also the job that
// `rgbmesh` runs without arguments (all defaults).

#include <cstddef>
#include <string>

namespace rgbmesh::cli {

struct AdaptArgs {
  std::string mesh;                    // empty: the embedded icosahedron
  std::string problem = "sphere-peak";  // sphere-harmonic, sphere-peak, moving-peak, gaussian
  std::string strategy = "adaptive";    // adaptive, uniform
  std::string marking = "dorfler";      // dorfler, fraction
  std::string estimator = "residual";   // residual, zz
  std::string geometry;                 // loop, sphere; empty: sphere for the sphere problems
  std::string solver = "auto";
  double theta = 0.5;
  double coarsen = -1;  // < 0: the problem's default (0.25 for moving-peak, else none)
  int cycles = 20;
  int steps = 24;  // moving-peak time steps
  double target_error = 0;
  std::size_t max_dofs = 100000;
  std::string out = "out";
  std::string report;  // JSON report path; empty: none
  bool quiet = false;
};

// Runs and writes everything; returns the exit code. Throws InputError on bad arguments.
int run_adapt(const AdaptArgs& args);

}  // namespace rgbmesh::cli
