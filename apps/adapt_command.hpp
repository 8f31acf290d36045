#pragma once
// `rgbmesh adapt`: error-driven adaptive cycles written for ParaView. It is also the job that
// `rgbmesh` runs without arguments (all defaults).

#include <array>
#include <cstdint>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "cli_options.hpp"
#include "rgbmesh/adapt/adaptive.hpp"
#include "rgbmesh/fem/solver.hpp"
#include "rgbmesh/vtk_io.hpp"

namespace rgbmesh::cli {

struct AdaptArgs {
  Compression compression = Compression::lz4;  // of the .vtp files (--compression)
  std::string mesh;                   // empty: the embedded icosahedron
  bool triangulate = false;           // split the mesh's polygons (polygons.hpp)
  bool repair = false;                // repair the mesh first (rgbmesh::repair)
  double sharp_angle = 0;             // > 0: edges sharper than this are creases (--sharp-angle)
  std::string problem;                // sphere-harmonic, sphere-peak, moving-peak, gaussian;
                                      // empty: sphere-peak, or gaussian with a --mesh
  std::string strategy = "adaptive";  // adaptive, uniform
  std::string marking;                // dorfler, fraction, equidistribution; empty: dorfler,
                                      // or equidistribution for moving-peak
  std::string estimator = "residual";  // residual, zz
  int order = 1;                       // finite elements: 1 (P1) or 2 (P2)
  std::string element;                 // p1, p2, loop; empty: P1 or P2 by --order
  std::string loop_basis = "details";  // Loop elements: details, thb (truncated hierarchical)
  std::string geometry;                // loop, sphere; empty: sphere for the sphere problems
  std::string solver = "auto";
  double theta = 0.5;
  double coarsen = -1;  // < 0: the problem's default (0.25 for moving-peak, else none)
  int cycles = 0;       // 0: 20, or 8 for moving-peak (the cycles adapting to the start)
  int steps = 24;       // moving-peak time steps
  double target_error = 0;
  std::int64_t max_dofs = 100000;
  int min_level = 0;  // a floor: no triangle coarser than this level
  double compact_below = 0.5;  // compact the mesh when fewer of its vertex slots are live
  std::vector<double> center;  // gaussian: the source's centre; empty: the first vertex's limit
  double width = 0;            // gaussian: sigma; 0: 1/20 of the bounding-box diagonal
  std::string out = "out";
  std::string report;  // JSON report path; empty: none
  std::set<std::string> given;  // the options the user gave ("--theta", ...), for refusals
  std::string command_line;     // for the report
  std::string memory_limit;     // the global --memory-limit ("" for the default)
  std::string resume;           // --resume DIR: continue the run in DIR; empty: a new run
  // Several processes (mpirun): whether this one writes the files and the report (rank 0),
  // how many there are, and what makes the adaptive loop run on all of them (given the
  // options complete, and whether the mesh may be distributed; rgbmesh::parallel::
  // distribute_mesh or distribute). Empty on one process.
  bool writes = true;
  int processes = 1, rank = 0;
  std::function<void(adapt::AdaptOptions&, bool may_distribute_mesh)> distribute;
};

// The subcommand's options on the tool, bound to `args` (the object must stay where add() saw it).
struct AdaptCommand {
  CLI::App* app = nullptr;
  CLI::Option* out = nullptr;
  AdaptArgs args;
  void add(CLI::App& tool, CompressionOption& compression);
  // Once parsed: the options given (AdaptArgs::given, for the refusals that depend on the
  // problem); an InputError for combinations refused before any work.
  void settle_given();
};

// Checks the arguments against each other and the mesh, runs, writes everything; returns the
// exit code. Throws InputError on bad arguments or input.
int run_adapt(const AdaptArgs& args);

}  // namespace rgbmesh::cli
