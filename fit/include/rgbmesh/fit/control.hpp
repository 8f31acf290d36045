#pragma once
/// \file
/// How the long stages of a fit (reconstruction, decimation, stencils, iterations) report their
/// progress and are stopped from outside: the caller supplies a function that each stage calls
/// between steps of bounded work (a fraction of a second at most). It may print progress, and
/// it may throw (the command-line tool throws a ResourceError when the process passes its memory
/// ceiling) to stop the stage: every stage leaves nothing half-built behind when it does.

#include <functional>
#include <string>

namespace rgbmesh::fit {

struct StageControl {
  /// Called with the stage's name ("reconstructing a surface from 6,000 points (Poisson)") and
  /// the fraction done, in [0, 1], or a negative number when the stage cannot tell.
  std::function<void(const std::string& stage, double fraction)> on_step;

  void step(const std::string& stage, double fraction = -1) const {
    if (on_step) on_step(stage, fraction);
  }
};

}  // namespace rgbmesh::fit
