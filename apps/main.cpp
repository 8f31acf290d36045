// rgbmesh: the command-line tool.
//
//   rgbmesh                      the main job on an embedded default problem
//   rgbmesh info MESH            statistics of a mesh
//   rgbmesh convert IN OUT       format conversion (through the RGB mesh checks)
//   rgbmesh refine IN OUT ...    selective refinement stages, in the order given
//   rgbmesh adapt ...            adaptive finite elements (adapt_command.cpp)
//   rgbmesh fit ...              a subdivision surface fitted to points (fit_command.cpp)
//
// Each subcommand registers its own options (mesh_commands.cpp, adapt_command.cpp,
// fit_command.cpp); this file holds the tool's global options and the dispatch.
//
// Exit codes: 0 success, 1 an output could not be written, 2 bad input or arguments, 3 out of
// resources (memory) or an internal failure (rgbmesh/errors.hpp).

#include <cstdlib>  // (defines __GLIBC__ where it applies)
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <unistd.h>  // execv

#include <CLI/CLI.hpp>
#include <fstream>
#include <iostream>
#include <string>

#include "adapt_command.hpp"
#include "cli_options.hpp"
#include "fit_command.hpp"
#include "mesh_commands.hpp"
#include "one_line.hpp"
#include "processes.hpp"
#include "resources.hpp"
#include "rgbmesh/errors.hpp"
#include "rgbmesh/fem/petsc_module.hpp"

using namespace rgbmesh;
using namespace rgbmesh::cli;

namespace {

void tune_allocator() {
#if defined(__GLIBC__)
  // The mesh's arrays grow in a few large steps. A fixed threshold keeps every large block in
  // its own mapping, returned to the system when the array moves; glibc's default raises the
  // threshold after the first such free, after which freed blocks stay in the heap and count
  // in the resident size.
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  // A library that PETSc's module brings (SuperLU_DIST) switches mappings off (M_MMAP_MAX 0)
  // and heap trimming too as it loads: every block then came from the heap and stayed resident
  // once freed, and a refinement that passed --memory-limit 600M by a quarter held a grown
  // queue's old 200 MB block. glibc's defaults again, here and after the module is loaded
  // (fem::petsc::set_after_load).
  mallopt(M_MMAP_MAX, 65536);
  mallopt(M_TRIM_THRESHOLD, 128 * 1024);
#endif
}

// Transparent huge pages for malloc's large blocks. Every block above 1 MB is a mapping of its
// own (tune_allocator), which each cycle's matrices and vectors fault in anew, 4 KiB at a time.
// Where the kernel gives huge pages only on request (THP mode "madvise", as Debian's cloud
// kernels do), glibc asks for them under the tunable glibc.malloc.hugetlb=1, which it reads
// only at start; so the tool restarts itself once with it set. Measured 2026-12-05 on the
// 2-core development machine, rgbmesh adapt, two rounds of one script (docs/performance.md):
// 0.79-0.88 of the time for P1 and 0.82-0.84 for P2 to 300,000 unknowns, 0.81-0.94 for Loop
// elements to 30,000; a third of the page faults; peak memory 0.5-3.5% more. Under an MPI
// launcher too (the restart keeps the process, its environment and its binding; MPI starts
// later): on two processes the moving peak's second step (940,000 unknowns coarsened to 61,000)
// took 11.8-12.6 s against 14.5-15.3 s without (2026-12-07). Not where
// GLIBC_TUNABLES already names malloc.hugetlb (the user's choice), not with
// RGBMESH_NO_HUGEPAGES set, and never twice: the restarted process finds
// RGBMESH_HUGEPAGES_RESTARTED, whatever glibc makes of GLIBC_TUNABLES (one that does not know
// the tunable may drop it from the environment). If the restart fails the tool goes on as it
// is. A restart loads the tool's libraries again (about 0.15 s), so only the long subcommands
// (refine, adapt, fit and the default job) restart: info and convert, run on many files, do
// not.
void restart_with_huge_pages(int argc, char** argv) {
#if defined(__linux__) && defined(__GLIBC__)
  for (const char* name : {"RGBMESH_NO_HUGEPAGES", "RGBMESH_HUGEPAGES_RESTARTED"})
    if (std::getenv(name) != nullptr) return;
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word == "info" || word == "convert" || word == "--help" || word == "-h" || word == "--version")
      return;
    if (word == "refine" || word == "adapt" || word == "fit") break;
  }
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  const std::string current = tunables != nullptr ? tunables : "";
  if (current.find("glibc.malloc.hugetlb") != std::string::npos) return;
  std::ifstream mode("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  if (!std::getline(mode, modes) || modes.find("[madvise]") == std::string::npos) return;
  const std::string value = (current.empty() ? "" : current + ":") + "glibc.malloc.hugetlb=1";
  if (setenv("RGBMESH_HUGEPAGES_RESTARTED", "1", 1) != 0 || setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0)
    return;
  execv("/proc/self/exe", argv);
#else
  (void)argc, (void)argv;
#endif
}

// The tool and its subcommands, with the options that stand before a subcommand.
struct Tool {
  CLI::App app{
      "rgbmesh: adaptive RGB subdivision meshes (Puppo & Panozzo, IEEE TVCG 2009),\n"
      "conforming at every step, with the limit surface of Loop subdivision.\n"
      "Without a subcommand, runs the default job (see `rgbmesh --help`)."};
  std::string out = "out", memory_limit;
  CLI::Option* out_option = nullptr;
  CompressionOption compression;
  InfoCommand info;
  ConvertCommand convert;
  RefineCommand refine;
  AdaptCommand adapt;
  FitCommand fit;

  Tool() {
    app.require_subcommand(0, 1);
    app.set_version_flag("--version", "rgbmesh " RGBMESH_VERSION);
    app.add_option(
           "--memory-limit", memory_limit,
           "Memory ceiling of the process: bytes with K/M/G/T, or a percentage of the available memory "
           "[default: 80%]; larger work is refused or stopped (exit code 3)")
        ->type_name("SIZE");
    compression.add_to(app)->capture_default_str();
    out_option =
        app.add_option("--out", out,
                       "Output directory of the default job, and of adapt and fit when given before the "
                       "subcommand")
            ->capture_default_str()
            ->check(kNonEmptyPath);
    info.add(app);
    convert.add(app, compression);
    refine.add(app, compression);
    adapt.add(app, compression);
    fit.add(app, compression);
  }
  Tool(const Tool&) = delete;  // the options point into it
  Tool& operator=(const Tool&) = delete;

  // After parsing: the options before the subcommand passed on to it; an InputError where
  // they do not apply.
  void settle(int argc, char** argv) {
    // Global options work wherever they stand: `rgbmesh --out D adapt` is `rgbmesh adapt --out D`.
    if (out_option->count() > 0) {
      if (adapt.app->parsed() && adapt.out->count() == 0) adapt.args.out = out;
      if (fit.app->parsed() && fit.out->count() == 0) fit.args.out = out;
      for (const CLI::App* sub : {info.app, convert.app, refine.app}) {
        if (sub->parsed()) throw InputError("--out: " + sub->get_name() + " writes no output folder");
      }
    }
    if (info.app->parsed() && compression.given_before_subcommand())
      throw InputError("--compression: info writes no file");
    adapt.args.compression = fit.args.compression = compression.value();
    adapt.settle_given();
    std::string line = "rgbmesh";
    for (int i = 1; i < argc; ++i) line += std::string(" ") + argv[i];
    adapt.args.command_line = fit.args.command_line = line;
    adapt.args.memory_limit = fit.args.memory_limit = memory_limit;
  }

  // Runs the parsed subcommand (or the main job); returns the exit code.
  int run(const Processes& processes) {
    const MemoryCeiling ceiling = MemoryCeiling::from_option(memory_limit);
    if (!ceiling.note().empty()) std::cerr << "rgbmesh: note: " << one_line(ceiling.note()) << "\n";
    // Only adapt runs on several processes; any other command is rank 0's alone.
    if (processes.rank != 0 && !adapt.app->parsed() &&
        (info.app->parsed() || convert.app->parsed() || refine.app->parsed() || fit.app->parsed()))
      return 0;
    if (info.app->parsed()) {
      info.run();
      return 0;
    }
    if (convert.app->parsed()) {
      convert.run(compression.value());
      return 0;
    }
    if (refine.app->parsed()) {
      refine.run(compression.value(), ceiling);
      return 0;
    }
    if (adapt.app->parsed()) {
      distribute(adapt.args, processes);
      return run_adapt(adapt.args);
    }
    if (fit.app->parsed()) return run_fit(fit.args);
    // The main job: rgbmesh adapt with its defaults.
    AdaptArgs defaults;
    defaults.out = out;
    defaults.command_line = adapt.args.command_line;
    defaults.memory_limit = memory_limit;
    defaults.compression = compression.value();
    distribute(defaults, processes);
    return run_adapt(defaults);
  }
};

}  // namespace

int main(int argc, char** argv) {
  restart_with_huge_pages(argc, argv);
  tune_allocator();
  rgbmesh::fem::petsc::set_after_load(tune_allocator);
  remove_temporaries_on_signals();
  const Processes processes = start_processes(&argc, &argv);
  Tool tool;
  try {
    tool.app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return tool.app.exit(e);  // --help, --version
    std::cerr << "rgbmesh: error: " << one_line(e.what()) << " (see --help)\n";
    return 2;
  }
  // A failure: one line (rank 0 speaks for the run), and on several processes, an end for all.
  const auto fail = [&processes](int code, const std::string& message) {
    std::cerr << "rgbmesh: " << one_line(message) << "\n";
    return finish(processes, code, message);
  };
  try {
    tool.settle(argc, argv);
    return tool.run(processes);
  } catch (const MeshDefectError& e) {
    // The one thing to try next: what --repair would do about this defect.
    return fail(2, std::string("error: ") + e.what() + " (--repair " + e.hint() + ")");
  } catch (const InputError& e) {
    return fail(2, std::string("error: ") + e.what());
  } catch (const OutputError& e) {
    return fail(1, std::string("error: ") + e.what());
  } catch (const ResourceError& e) {
    return fail(3, std::string("error: ") + e.what());
  } catch (const std::bad_alloc&) {
    return fail(3, "error: out of memory (the work needs more memory than the machine has; see --memory-limit)");
  } catch (const std::exception& e) {
    return fail(3, std::string("internal error: ") + e.what());
  }
}
