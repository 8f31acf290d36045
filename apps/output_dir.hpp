#pragma once
// The output folder of `rgbmesh adapt` and `rgbmesh fit`.
//
// The rule: a run owns the rgbmesh files in its folder. Before writing anything, it removes
// every file that a run of `adapt` or `fit` writes there (cycle_NNN.vtp, step_NNN.vtp,
// cycle_NNN_p2.vtu, step_NNN_p2.vtu,
// solution.pvd, fitted_base.obj, limit_surface.vtp, initial_limit_surface.vtp, targets.vtp,
// base.obj, report.json), whichever subcommand wrote them, and the temporaries of atomic writes
// whose process is gone (a SIGKILL leaves them), and leaves every other file alone.
// So the folder never mixes the files of two runs, and a user's own files are never touched.

#include <filesystem>
#include <string>

namespace rgbmesh::cli {

// True for the names listed above.
bool is_run_output(const std::string& file_name);

// Creates `dir` (and its parents) if needed. OutputError naming the folder if it cannot be
// created or is not a folder (the CLI's exit code 1).
void create_output_directory(const std::filesystem::path& dir);

// Creates `dir` (and its parents) if needed and removes the outputs of a previous run, with
// a note on standard error saying how many. OutputError naming the folder if it cannot be
// created or is not a folder (the CLI's exit code 1).
void prepare_output_directory(const std::filesystem::path& dir);

}  // namespace rgbmesh::cli
