// The stiffmsa command's subcommands (the command module, app/command_module.hpp): parses the
// command line, runs the library, and turns every failure into a message on stderr and an exit
// code. What is printed is formatted in summary.cpp.
#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "merge_command.hpp"
#include "stiffmsa/config.hpp"
#include "stiffmsa/stiffmsa.hpp"
#include "summary.hpp"
#include "sweep_command.hpp"
#include "view_command.hpp"

namespace {

namespace fs = std::filesystem;
using namespace stiffmsa;
using namespace stiffmsa::cli;

struct SolveCommand {
  std::string model_file;
  std::string json_file;  // empty: no result file
  std::string vtk_file;   // empty: no ParaView file
  std::string solver = "auto";
  bool accept_idle_motions = false;
  std::vector<std::string> settings;  // parametric models: "name=value"
  std::string direction;              // "x,y,z": also the stiffness along it
  bool critical_load = false;         // --critical-load
  bool no_critical_load = false;      // --no-critical-load
  LoadLimits limits;
  bool loaded = false;  // the loaded mode, whatever the model's `analysis:` says
};

struct CheckCommand {
  std::string model_file;
  LoadLimits limits;
};

// The run ends with the process: a model kept here is left for the exit to release with the rest
// of the heap, rather than freed one allocation at a time just before (a 1 015-beam model's
// names, origins and key locations: 4.5 M instructions, bench/README.md). The pointer, never
// freed, keeps it reachable for a leak checker.
template <class T>
const T& kept_until_exit(T value) {
  static auto* const kept = new std::vector<std::unique_ptr<T>>;
  kept->push_back(std::make_unique<T>(std::move(value)));
  return *kept->back();
}

// A result file written over the model would destroy the user's input.
void refuse_to_overwrite_model(const fs::path& model_file, const fs::path& json_file) {
  if (same_file(model_file, json_file)) {
    throw UsageError("the result file '" + json_file.string() +
                     "' is the model file; choose another name for --json");
  }
}

SolveOptions solve_options(const std::string& solver, bool accept_idle_motions,
                           const std::string& direction) {
  SolveOptions options;
  if (!direction.empty()) options.direction = parse_direction(direction);
  // CLI11 has already checked the name against the list of solvers.
  options.solver = solver_kind_from_string(solver).value_or(SolverKind::automatic);
  options.accept_idle_motions = accept_idle_motions;
  if (!solver_available(options.solver)) {
    throw UsageError("solver '" + solver +
                     "' is not available in this build of stiffmsa (built without SuiteSparse); "
                     "use --solver auto or sparse_lu");
  }
  options.validate();
  return options;
}

int run_solve(const SolveCommand& command) {
  std::optional<fs::path> json_file;
  if (!command.json_file.empty()) {
    json_file = command.json_file;
    refuse_to_overwrite_model(command.model_file, *json_file);
  }
  if (!command.vtk_file.empty()) refuse_to_overwrite_model(command.model_file, command.vtk_file);
  SolveOptions options =
      solve_options(command.solver, command.accept_idle_motions, command.direction);
  if (command.loaded) options.mode = AnalysisMode::loaded;
  // Without --set the file is read once, as any model; with it, as a family.
  const Model& model = kept_until_exit([&] {
    if (command.settings.empty()) return load_model(command.model_file, command.limits);
    const ModelFamily family =
        load_model_family(command.model_file, command.limits, parse_settings(command.settings));
    return family.build(family.default_values());
  }());
  // Without either flag, the result file's contract decides (SolveOptions::critical_load).
  if (command.critical_load) options.critical_load = true;
  if (command.no_critical_load) options.critical_load = false;
  const Result result = solve(model, options);
  // Written before the summary, so that a summary on screen means the file is there too.
  if (json_file) write_result_file(result, *json_file);
  const auto vtk_files = command.vtk_file.empty() ? std::vector<fs::path>{}
                                                  : write_vtk(model, result, command.vtk_file);
  print_solve_summary(std::cout, result, json_file);
  for (const fs::path& file : vtk_files)
    std::cout << "ParaView file written to " << file.string() << '\n';
  return exit_success;
}

// The plain model a robot block (or any model file) makes at one pose, to see and edit.
struct ExpandCommand {
  std::string model_file;
  std::string output_file;  // empty: standard output
  std::vector<std::string> settings;
  LoadLimits limits;
};

int run_expand(const ExpandCommand& command) {
  const ModelFamily family =
      load_model_family(command.model_file, command.limits, parse_settings(command.settings));
  const Model model = family.build(family.default_values());
  if (command.output_file.empty()) {
    std::cout << model_to_yaml(model);
    return exit_success;
  }
  if (same_file(command.model_file, command.output_file))
    throw UsageError("the output file '" + command.output_file +
                     "' is the model file; choose another name for --output");
  write_model_file(model, command.output_file);
  return exit_success;
}

int run_check(const CheckCommand& command) {
  const Model model = load_model(command.model_file, command.limits);
  print_check_summary(std::cout, model, check(model), find_implausible_values(model));
  return exit_success;
}

// A whole number of at least 1. (CLI::PositiveNumber prints its bounds as 300-digit doubles.)
const CLI::Validator at_least_one(
    [](std::string& input) -> std::string {
      std::uint64_t value = 0;
      const char* end = input.data() + input.size();
      const auto [stop, error] = std::from_chars(input.data(), end, value);
      if (error != std::errc() || stop != end || value == 0)
        return "expected a whole number of at least 1, got '" + input + "'";
      return {};
    },
    "N >= 1");

// The bounds on a model file (LoadLimits), for a file larger than real models are.
void add_solver_option(CLI::App& command, std::string& solver) {
  command
      .add_option("--solver", solver,
                  "auto (tree-shaped models without factorising, parallel robots among them "
                  "through a small "
                  "dense system for their cuts; else klu, or sparse_lu where klu would fill in), "
                  "or a sparse LU: "
                  "sparse_lu, umfpack, klu")
      ->check(CLI::IsMember({"auto", "sparse_lu", "umfpack", "klu"}))
      ->capture_default_str();
}

void add_limit_options(CLI::App& command, LoadLimits& limits) {
  command
      .add_option("--max-file-size", limits.max_file_bytes,
                  "Refuse a larger model file; bytes, or with a unit: 200MiB, 500MB")
      ->transform(CLI::AsSizeValue(true))
      ->check(at_least_one)
      ->capture_default_str();
  command
      .add_option("--max-depth", limits.max_nesting_depth,
                  "Refuse a model file whose mappings and lists nest deeper")
      ->check(at_least_one)
      ->capture_default_str();
  command
      .add_option("--max-entities", limits.max_entities,
                  "Refuse a model with more points, links, joints, supports, loads or end "
                  "effectors (each kind counted alone)")
      ->check(at_least_one)
      ->capture_default_str();
}

int run(int argc, char** argv) {
  CLI::App app{"stiffmsa: stiffness of robot manipulators by extended matrix structural analysis",
               "stiffmsa"};
  app.set_version_flag("--version", std::string("stiffmsa ") + STIFFMSA_VERSION);
  app.require_subcommand(1);

  SolveCommand solve_command;
  CLI::App* solve_app =
      app.add_subcommand("solve", "Solve a model and print the stiffness of its end effectors");
  solve_app->add_option("MODEL", solve_command.model_file, "Model file (YAML or JSON)")->required();
  solve_app->add_option("--json", solve_command.json_file, "Write the result file to this path");
  solve_app->add_option(
      "--vtk", solve_command.vtk_file,
      "Write a ParaView file: OUT.vtu, or OUT.pvd with a .vtu per load case beside it");
  add_solver_option(*solve_app, solve_command.solver);
  solve_app->add_flag("--accept-idle-motions", solve_command.accept_idle_motions,
                      "Solve despite free motions that move no end effector (the spin of a "
                      "leg about its own axis); as `options: {accept_idle_motions: true}`");
  solve_app->add_option("--set", solve_command.settings,
                        "Parametric models: a parameter's value, NAME=VALUE (repeatable)");
  solve_app->add_option(
      "--direction", solve_command.direction,
      "Also the stiffness along this direction, X,Y,Z in global axes (any length), e.g. 0,0,1");
  CLI::Option* critical_load =
      solve_app->add_flag("--critical-load", solve_command.critical_load,
                          "Also the critical load factor: the multiple of the loads at which the "
                          "structure buckles (always given for load cases, loads along links, "
                          "gravity, settlements and the loaded mode)");
  solve_app
      ->add_flag("--no-critical-load", solve_command.no_critical_load,
                 "Never the critical load factor, also where it is given unasked: saves its "
                 "cost; every other number is the same")
      ->excludes(critical_load);
  add_limit_options(*solve_app, solve_command.limits);
  solve_app->add_flag("--loaded", solve_command.loaded,
                      "The loaded mode: equilibrium in the deformed geometry and the tangent "
                      "stiffness there; as `analysis: {mode: loaded}`");

  CheckCommand check_command;
  CLI::App* check_app =
      app.add_subcommand("check", "Validate a model and print its system size without solving");
  check_app->add_option("MODEL", check_command.model_file, "Model file (YAML or JSON)")->required();
  add_limit_options(*check_app, check_command.limits);

  SweepCommand sweep_command;
  std::string sweep_solver = "auto";
  bool sweep_accept_idle_motions = false;
  std::string sweep_direction;
  CLI::App* sweep_app = app.add_subcommand(
      "sweep",
      "Solve a parametric model over a grid or a list of poses and write one CSV row per pose");
  sweep_app->add_option("MODEL", sweep_command.model_file, "Model file with `parameters:`")
      ->required();
  sweep_app->add_option("--csv", sweep_command.csv_file, "Write the rows to this CSV file");
  sweep_app->add_option("--hdf5", sweep_command.hdf5_file,
                        "Write the rows to this HDF5 file (beside or instead of --csv)");
  sweep_app->add_option(
      "--shard", sweep_command.shard,
      "Solve only the K-th of N equal parts of the poses, K/N (join them with `stiffmsa merge`)");
  sweep_app
      ->add_option("--block", sweep_command.block,
                   "Poses solved and written at a time (memory, MPI balance)")
      ->check(at_least_one)
      ->capture_default_str();
  sweep_app->add_option(
      "--grid", sweep_command.grids,
      "A swept parameter: NAME=START:STOP:COUNT, both ends included (repeatable; the first "
      "varies fastest)");
  sweep_app->add_option(
      "--poses", sweep_command.poses_file,
      "A CSV whose header names parameters and whose rows are poses (instead of --grid)");
  sweep_app->add_option(
      "--set", sweep_command.settings,
      "A parameter held at another value than its default, NAME=VALUE (repeatable)");
  sweep_app->add_flag("--full", sweep_command.full,
                      "Also write the 36 compliance and 36 stiffness entries per end effector");
  sweep_app->add_flag("--plot", sweep_command.plot,
                      "Draw PNG and SVG maps (2-D grid) or line plots (1-D grid) beside the CSV");
  sweep_app->add_flag("--view", sweep_command.view,
                      "Write an HTML map beside the CSV: the pose under the mouse with its values "
                      "(and ellipsoids with --full)");
  sweep_app->add_option(
      "--plot-column", sweep_command.plot_columns,
      "A column to plot (repeatable); default: E.k_trans_min and E.deflection_trans of "
      "every end effector E");
  sweep_app->add_option("--summary", sweep_command.summary_file,
                        "Write the JSON summary here (default: beside the CSV, NAME.summary.json)");
  sweep_app->add_option("--threads", sweep_command.threads, "Threads to use (default: every core)")
      ->check(at_least_one);
  sweep_app->add_flag("--quiet", sweep_command.quiet, "No progress bar");
  add_solver_option(*sweep_app, sweep_solver);
  sweep_app->add_flag("--accept-idle-motions", sweep_accept_idle_motions,
                      "Solve despite free motions that move no end effector");
  sweep_app->add_option(
      "--direction", sweep_direction,
      "Add the columns E.k_trans_dir and E.k_rot_dir: the stiffness along X,Y,Z (global axes)");
  sweep_app->add_option("--case", sweep_command.load_case,
                        "The named load case whose results the rows take (default: the "
                        "top-level results)");
  add_limit_options(*sweep_app, sweep_command.limits);
  bool sweep_loaded = false;
  sweep_app->add_flag("--loaded", sweep_loaded, "The loaded mode at every pose; as for solve");

  ViewCommand view_command;
  std::string view_solver = "auto";
  bool view_accept_idle_motions = false;
  CLI::App* view_app = add_view_subcommand(app, view_command);
  add_solver_option(*view_app, view_solver);
  view_app->add_flag("--accept-idle-motions", view_accept_idle_motions, "As for solve");
  add_limit_options(*view_app, view_command.limits);
  ExpandCommand expand_command;
  CLI::App* expand_app = app.add_subcommand("expand",
                                            "Write the plain model (format stiffmsa/1) that a "
                                            "robot block or parameters make at one pose");
  expand_app->add_option("MODEL", expand_command.model_file, "Model file (YAML or JSON)")
      ->required();
  expand_app->add_option("-o,--output", expand_command.output_file,
                         "Write the model here (default: standard output)");
  expand_app->add_option("--set", expand_command.settings,
                         "A parameter's value, NAME=VALUE (repeatable)");
  add_limit_options(*expand_app, expand_command.limits);

  MergeCommand merge_command;
  CLI::App* merge_app = add_merge_subcommand(app, merge_command);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version arrive here too, with exit code 0.
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    print_error(std::cerr, e.what());
    std::cerr << "Run 'stiffmsa --help' for usage.\n";
    return exit_invalid_input;
  }

  if (solve_app->parsed()) return run_solve(solve_command);
  if (view_app->parsed()) {
    view_command.solve = solve_options(view_solver, view_accept_idle_motions, {});
    return run_view(view_command);
  }
  if (expand_app->parsed()) return run_expand(expand_command);
  if (sweep_app->parsed()) {
    sweep_command.solve = solve_options(sweep_solver, sweep_accept_idle_motions, sweep_direction);
    if (sweep_loaded) sweep_command.solve.mode = AnalysisMode::loaded;
    return run_sweep(sweep_command);
  }
  if (merge_app->parsed()) return run_merge(merge_command);
  return run_check(check_command);
}

}  // namespace

namespace {

// Allocations up to this size come from the heap, not from mmap (glibc's largest setting), and
// up to this much freed memory at the heap's top stays with the process.
constexpr int kKeptAllocationBytes = 32 << 20;
constexpr int kKeptFreeBytes = 256 << 20;
// The heap's first stretch, asked for in transparent huge pages.
constexpr std::size_t kHugePageHeapBytes = std::size_t{64} << 20;
constexpr std::uintptr_t kHugePageBytes = std::uintptr_t{2} << 20;
constexpr int kDefaultTopPadBytes = 128 << 10;          // glibc's M_TOP_PAD
constexpr std::uintptr_t kNoHeap = ~std::uintptr_t{0};  // sbrk's failure, (void*)-1

// A run allocates, frees and allocates again (the file's tree, the model, the assembled system,
// the result's text) and then exits. Freed memory is kept for the next allocation instead of
// going back to the kernel, which would hand it out again as fresh zeroed pages; and the heap's
// first 64 MiB are reserved at once and advised as transparent huge pages (where the system
// gives them on request, /sys/kernel/mm/transparent_hugepage/enabled = madvise or always), so
// that a solve's megabytes of fresh heap fault in 2 MiB at a time rather than 4 KiB: the
// 1 015-beam lattice's solve took 4 000 page faults, a fifth of its time (bench/README.md).
// glibc does the latter with GLIBC_TUNABLES=glibc.malloc.hugetlb=1, which a program cannot set
// for itself once started. Both are requests: where refused, the run is as before.
void prepare_heap() {
  mallopt(M_MMAP_THRESHOLD, kKeptAllocationBytes);
  mallopt(M_TRIM_THRESHOLD, kKeptFreeBytes);
  const auto heap_top = [] { return reinterpret_cast<std::uintptr_t>(sbrk(0)); };
  const std::uintptr_t bottom = heap_top();
  mallopt(M_TOP_PAD, static_cast<int>(kHugePageHeapBytes));
  // Grows the heap by the pad, which stays (volatile: a compiler may drop a malloc and its free).
  void* volatile block = std::malloc(std::size_t{1} << 20);
  std::free(block);
  mallopt(M_TOP_PAD, kDefaultTopPadBytes);
  const std::uintptr_t top = heap_top();
  // Only the stretch this grew (an allocator that did not, a sanitizer's, leaves it alone).
  const std::uintptr_t start = (bottom + kHugePageBytes - 1) & ~(kHugePageBytes - 1);
  if (bottom != kNoHeap && top != kNoHeap && top >= bottom + kHugePageHeapBytes && start < top)
    madvise(reinterpret_cast<void*>(start), top - start, MADV_HUGEPAGE);
}

}  // namespace

// The command module's entry (app/command_module.hpp), called by the launcher (app/launcher.cpp).
extern "C" __attribute__((visibility("default"))) int stiffmsa_command_main(
    int argc, char** argv, const char* launcher_version) {
  if (std::string_view(launcher_version) != STIFFMSA_VERSION) {
    std::cerr << "stiffmsa: error: the command module is stiffmsa " << STIFFMSA_VERSION
              << " but the executable stiffmsa " << launcher_version << ": install them together\n";
    return exit_invalid_input;
  }
  prepare_heap();
  int code = exit_success;
  try {
    code = run(argc, argv);
  } catch (...) {
    code = report_current_exception();
  }
  // A summary that could not be printed (a full disk behind a redirection) is a failed run.
  if (!std::cout.flush() && code == exit_success) {
    std::cerr << "stiffmsa: error: cannot write to standard output\n";
    code = exit_invalid_input;
  }
  return code;
}
