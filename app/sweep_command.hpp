#pragma once
// `stiffmsa sweep`: a model family solved over a grid or a list of poses, written as a CSV with
// a JSON summary beside it and, on request, stiffness maps.
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "stiffmsa/stiffmsa.hpp"
#include "sweep_output.hpp"

namespace stiffmsa::cli {

struct SweepCommand {
  std::string model_file;
  std::string csv_file;            // empty: no CSV (then hdf5_file)
  std::string hdf5_file;           // empty: no HDF5
  std::string shard;               // "K/N": the K-th of N parts of the poses; empty: all
  std::size_t block = 4096;        // poses solved, passed on and written at a time
  std::string summary_file;        // empty: beside the CSV, <stem>.summary.json
  std::vector<std::string> grids;  // "name=start:stop:count"
  std::string poses_file;
  std::vector<std::string> settings;  // "name=value": parameters held at other than defaults
  bool full = false;
  bool plot = false;
  bool view = false;  // an HTML map beside the CSV (docs/viewer.md)
  std::vector<std::string>
      plot_columns;  // empty: k_trans_min and deflection_trans per end effector
  std::size_t threads = 0;
  bool quiet = false;
  SolveOptions solve;
  LoadLimits limits;
  std::string load_case;  // --case: the named load case whose results the rows take
};

int run_sweep(const SweepCommand& command);

// The poses of a run (all, or a shard's) and how to solve a block of them.
struct SweepPlan {
  const ModelFamily* family = nullptr;
  SweepOptions options;
  std::vector<GridAxis> axes;         // a grid, made block by block; empty: `listed`
  const PoseTable* listed = nullptr;  // the pose file's poses
  std::size_t first = 0, end = 0;     // this run's poses
  std::size_t block = 4096;

  SweepResult solve(std::size_t first, std::size_t count,
                    const std::function<void(std::size_t, std::size_t)>& progress = {}) const;
};

// A sweep command checked and its model read, ready to run (here or over MPI ranks). Throws
// UsageError, InputError, IoError before any pose is solved.
struct PreparedSweep {
  std::optional<ModelFamily> family;
  std::vector<GridAxis> axes;
  PoseTable listed;
  SweepDescription description;
  SweepFiles files;
  SweepPlan plan;                   // points into this object: not to be copied
  std::string extra_summary;        // JSON object: a shard's part and identity
  std::filesystem::path view_file;  // --view's HTML map; empty: none
  PreparedSweep() = default;
  PreparedSweep(const PreparedSweep&) = delete;
  PreparedSweep(PreparedSweep&&) = delete;
};
std::unique_ptr<PreparedSweep> prepare_sweep(const SweepCommand& command);

// Whether two paths name the same file (existing or not), for refusing to write over an input.
bool same_file(const std::filesystem::path& a, const std::filesystem::path& b);

// The "name=value" pairs of --set (sweep and solve). Throws UsageError.
ParameterSettings parse_settings(const std::vector<std::string>& settings);

// The "x,y,z" of --direction (solve and sweep): three finite numbers, not all zero. Throws
// UsageError.
Vec3 parse_direction(const std::string& text);

}  // namespace stiffmsa::cli
