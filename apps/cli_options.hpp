#pragma once
// What several subcommands' options share (CLI11): checks, help texts and --compression.

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "rgbmesh/vtk_io.hpp"

namespace rgbmesh::cli {

// A check that a path option names something: an empty value (an unset shell variable,
// `--resume "$RUN"`) would otherwise be taken as "not given" and, for --resume, start a new run
// over the folder's previous one.
extern const CLI::Validator kNonEmptyPath;

// A check that the option's value is a number accepted by `ok`; the message names what is
// expected and what was given ("--theta: must be a number in (0, 1], got 0").
CLI::Validator number_in(const std::string& what, bool (*ok)(double));

// The help of every --repair flag.
extern const char* const kRepairHelp;

// --sharp-angle DEG on a subcommand that reads a mesh (SoupOptions::sharp_angle); 0 when not given.
CLI::Option* add_sharp_angle(CLI::App* app, double& degrees);

// The names of a library's table (marking_table, estimator_table) for an option's help.
template <class Row>
std::string choices_help(const std::vector<Row>& table) {
  std::string help;
  for (std::size_t i = 0; i < table.size(); ++i)
    help += (i == 0                  ? ""
             : i + 1 == table.size() ? " or "
                                     : ", ") +
            std::string(table[i].name) + " (" + table[i].description + ")";
  return help;
}

// --compression: before the subcommand, or on any subcommand that writes files; every copy
// writes the same value.
class CompressionOption {
 public:
  CLI::Option* add_to(CLI::App& where);
  Compression value() const;  // (checked by the options' validator)
  bool given_before_subcommand() const { return !options_.empty() && options_.front()->count() > 0; }

 private:
  std::string text_ = compression_name(WriteOptions().compression);
  std::vector<CLI::Option*> options_;
};

}  // namespace rgbmesh::cli
