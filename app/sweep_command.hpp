#pragma once
// `stiffmsa sweep`: a model family solved over a grid or a list of poses, written as a CSV with
// a JSON summary beside it and, on request, stiffness maps.
#include <filesystem>
#include <string>
#include <vector>

#include "stiffmsa/stiffmsa.hpp"

namespace stiffmsa::cli {

struct SweepCommand {
  std::string model_file;
  std::string csv_file;
  std::string summary_file;  // empty: beside the CSV, <stem>.summary.json
  std::vector<std::string> grids;  // "name=start:stop:count"
  std::string poses_file;
  std::vector<std::string> settings;  // "name=value": parameters held at other than defaults
  bool full = false;
  bool plot = false;
  bool view = false;  // an HTML map beside the CSV (docs/viewer.md)
  std::vector<std::string> plot_columns;  // empty: k_trans_min and deflection_trans per end effector
  std::size_t threads = 0;
  bool quiet = false;
  SolveOptions solve;
  LoadLimits limits;
};

int run_sweep(const SweepCommand& command);

// Whether two paths name the same file (existing or not), for refusing to write over an input.
bool same_file(const std::filesystem::path& a, const std::filesystem::path& b);

// The "name=value" pairs of --set (sweep and solve). Throws UsageError.
ParameterSettings parse_settings(const std::vector<std::string>& settings);

// The "x,y,z" of --direction (solve and sweep): three finite numbers, not all zero. Throws
// UsageError.
Vec3 parse_direction(const std::string& text);

}  // namespace stiffmsa::cli
