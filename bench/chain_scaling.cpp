// One straight chain of N beam links per process, so that the peak memory (VmHWM) belongs to
// that N alone: prints one JSON line with the times of building the model, the whole solve
// from scratch, the workspace alone and a repeated solve with the workspace kept; the peak
// memory; and the tip compliance against its closed form.
//
//   stiffmsa_chain N|FILE.yaml [sparse_lu|umfpack|klu] [--refinement-steps K] [--once]
//
// With a model file (bench/make_models.py chain N), the model is read with load_model and
// "build_model_s" is the time to read it. --once stops after the solve from scratch (for
// profiling it alone).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

#include "bench_models.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// A field of /proc/self/status in kB (VmRSS, VmHWM), or -1.
long status_kib(const std::string& field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind(field + ":", 0) == 0) return std::atol(line.c_str() + field.size() + 1);
  return -1;
}

}  // namespace

int main(int argc, char** argv) {
  const char* usage =
      "usage: stiffmsa_chain N|FILE.yaml [sparse_lu|umfpack|klu] [--refinement-steps K] [--once]\n";
  if (argc < 2) {
    std::cerr << usage;
    return 2;
  }
  const std::string source = argv[1];
  const bool from_file = source.ends_with(".yaml");
  stiffmsa::SolveOptions options;
  bool once = false;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--once") {
      once = true;
    } else if (arg == "--refinement-steps" && i + 1 < argc) {
      options.refinement_steps = std::atoi(argv[++i]);
    } else if (const auto kind = stiffmsa::solver_kind_from_string(arg);
               kind && stiffmsa::solver_available(*kind)) {
      options.solver = *kind;
    } else {
      std::cerr << "stiffmsa_chain: unknown or unavailable '" << arg << "'\n" << usage;
      return 2;
    }
  }

  auto start = Clock::now();
  const stiffmsa::Model model =
      from_file ? stiffmsa::load_model(source) : bench::cantilever_chain(std::stoi(source));
  const int links = static_cast<int>(model.links.size());
  const double build_model_s = seconds_since(start);
  const long model_rss_kib = status_kib("VmRSS");

  start = Clock::now();
  const stiffmsa::Result result = stiffmsa::solve(model, options);
  const double solve_s = seconds_since(start);
  const long peak_kib = status_kib("VmHWM");  // before anything else is allocated
  double workspace_s = 0, first_s = 0, repeat_s = 0;
  if (!once) {
    // The same again in steps: the workspace (validation, topology, pattern), the first solve
    // with it (pattern analysis + numeric work), and a repeated solve (numeric work only).
    start = Clock::now();
    stiffmsa::Workspace workspace(model);
    workspace_s = seconds_since(start);
    start = Clock::now();
    stiffmsa::solve(workspace, model, options);
    first_s = seconds_since(start);
    start = Clock::now();
    stiffmsa::solve(workspace, model, options);
    repeat_s = seconds_since(start);
  }

  const stiffmsa::Mat6 expected = bench::cantilever_tip_compliance();
  const stiffmsa::Mat6& c = *result.end_effectors.front().compliance;
  std::printf(
      "{\"links\": %d, \"source\": \"%s\", \"solver\": \"%s\", \"refinement_steps\": %d, "
      "\"unknowns\": %ld, \"nonzeros\": %ld, "
      "\"build_model_s\": %.6f, \"solve_s\": %.6f, \"workspace_s\": %.6f, \"first_solve_s\": %.6f, "
      "\"repeat_solve_s\": %.6f, \"model_rss_mib\": %.1f, \"peak_mib\": %.1f, \"tip_error\": %.3e, "
      "\"cyy_error\": %.3e, \"relative_residual\": %.3e, \"warnings\": %zu}\n",
      links, from_file ? "file" : "code", stiffmsa::to_string(options.solver),
      options.refinement_steps, result.system.unknowns, result.system.nonzeros, build_model_s,
      solve_s, workspace_s, first_s, repeat_s, model_rss_kib / 1024.0, peak_kib / 1024.0,
      bench::scaled_difference(c, expected), std::abs(c(1, 1) / expected(1, 1) - 1),
      result.report.relative_residual, result.report.warnings.size());
  return 0;
}
