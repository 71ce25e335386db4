#pragma once
// Where a sweep's rows go, block by block in pose order: the CSV and/or HDF5 file, the summary
// gathered on the way, and the values of the plotted columns. One run, a merge of shards and
// the first MPI rank all write through it, so that they write the same files.
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "stiffmsa/stiffmsa.hpp"

namespace stiffmsa::cli {

// What a sweep is, as its summary describes it.
struct SweepDescription {
  // Model, swept parameters with units and grid, end effectors, fixed parameters, direction,
  // warnings (no results).
  SweepResult run;
  std::string loads;  // the loads deflection maps are drawn under: "F (0, 0, -100) N at E"
  bool full = false;
  std::vector<SweepColumn> columns;
  std::size_t poses = 0;  // in the whole sweep
};

// One block of consecutive poses, solved: the rows, what they add to the summary and, when a
// CSV is written, the rows as its lines.
struct SweepBlock {
  SweepRows rows;
  SweepSummary summary;
  std::string csv;
  std::vector<double> plotted;  // the plotted columns' values, row-major
  std::size_t threads = 1;
  double seconds = 0;
};

// What a block must carry for the output that writes it.
struct BlockShape {
  const SweepDescription* description = nullptr;
  std::vector<SweepColumn> plotted;
  bool csv = false;   // the rows as CSV lines
  bool rows = false;  // the rows' values (HDF5)
};

struct SweepFiles {
  std::filesystem::path csv;   // empty: none
  std::filesystem::path hdf5;  // empty: none
  std::filesystem::path summary;
  std::vector<SweepColumn> plotted;  // empty: no plots
  std::filesystem::path plot_base;   // plots are <plot_base>.<column>.png / .svg
};

class SweepOutput {
 public:
  // The files are created now (as temporaries) and appear whole at finish().
  SweepOutput(const SweepDescription& description, SweepFiles files, std::size_t first_pose,
              std::size_t poses);
  SweepOutput(const SweepOutput&) = delete;
  SweepOutput& operator=(const SweepOutput&) = delete;
  ~SweepOutput();

  BlockShape shape() const;
  // The files being written, for removing them when the process is killed.
  std::vector<std::filesystem::path> temporary_files() const;

  // The next block, in pose order.
  void write(const SweepBlock& block);
  // Writes the summary (with `extra` keys merged in, a JSON object's text) and the plots and
  // puts every file in place; returns the files written.
  std::vector<std::filesystem::path> finish(std::size_t threads, double seconds,
                                            const std::string& extra_json = {});

  const SweepSummary& summary() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// What `output` needs of the rows of consecutive poses from `first_pose` on: their CSV lines if
// it writes a CSV, their values if it writes HDF5, the plotted columns' values if it plots.
SweepBlock make_block(const BlockShape& shape, const SweepResult& solved, std::size_t first_pose);
SweepBlock make_block(const BlockShape& shape, SweepRows rows);

// A bar on the terminal, for sweeps long enough to wait for; nothing when stderr is a file.
class ProgressBar {
 public:
  explicit ProgressBar(bool enabled);
  void update(std::size_t done, std::size_t total);
  // Clears the bar, so that what is printed next starts on a clean line.
  void finish();
  ~ProgressBar() { finish(); }

 private:
  double seconds_since_start() const;
  bool enabled_;
  bool drawn_ = false;
  double last_drawn_ = 0;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// What the command prints at the end: poses, rate, fixed parameters, warnings, statuses, first
// pose with large deflections, first failure, worst of each column, the files written.
void print_sweep_summary(std::ostream& out, const SweepDescription& description,
                         const SweepSummary& summary, std::size_t threads, double seconds,
                         const std::vector<std::filesystem::path>& files, std::size_t ranks = 1);

// The columns `--plot-column` names (default: E.k_trans_min and E.deflection_trans of every end
// effector). Throws UsageError naming the columns there are.
std::vector<SweepColumn> plotted_columns(const SweepResult& description,
                                         const std::vector<std::string>& names);

// A plot or a view map holds a number per pose: sweeps of more poses are refused them.
constexpr std::size_t kMaxPosesInMemory = 10'000'000;

// The loads of `model` as a plot's subtitle says them: "F (0, 0, -100) N at E"; at most two,
// then how many more.
std::string loads_text(const Model& model);

// What --plot needs of the grid. Throws UsageError.
void check_plot_grid(const std::vector<GridAxis>& axes, bool from_pose_file);

}  // namespace stiffmsa::cli
