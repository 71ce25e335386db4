#pragma once
// Sweep files: the poses a user lists (CSV in), one result row per pose (CSV out) and a JSON
// summary naming the worst pose of every column (docs/model-format.md, "Sweep files").
#include <array>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "stiffmsa/sweep.hpp"

namespace stiffmsa {

// A CSV whose header names parameters and whose rows give their values; `#` lines and blank
// lines are skipped. Throws IoError when it cannot be read and InputError (file:line, column)
// for a defect.
PoseTable read_pose_table(const std::filesystem::path& file);
PoseTable parse_pose_table(std::string_view text, const std::string& file_name);

// A number as pose files, grids and `--set` values write it: all of the text is a finite
// decimal number, with an optional leading '+'.
std::optional<double> parse_plain_number(std::string_view text);

// The columns of a sweep's result, after the swept parameters, `status` and `message`:
// per end effector E, E.k_trans_min … E.deflection_rot, E.cond_trans, with a direction
// E.k_trans_dir and E.k_rot_dir, and with `full` E.C11 … E.K66.
enum class SweepQuantity {
  k_trans_min,
  k_trans_max,
  k_rot_min,
  k_rot_max,
  deflection_trans,
  deflection_rot,
  compliance,
  stiffness,
  cond_trans,
  k_trans_dir,
  k_rot_dir,
};
struct SweepColumn {
  std::string name;  // e.g. "platform.k_trans_min"
  std::string unit;  // SI, e.g. "N/m"
  SweepQuantity quantity;
  std::size_t end_effector;  // index in SweepResult::end_effectors
  int row = 0, col = 0;      // compliance and stiffness entries, 0-based
  // Deflections, compliances and stiffness couplings (off-diagonal) are worst where
  // largest, stiffness where smallest; matrix entries by magnitude.
  bool worst_is_largest = false;
};
std::vector<SweepColumn> sweep_columns(const SweepResult& sweep, bool full);
std::optional<SweepColumn> find_sweep_column(const SweepResult& sweep, const std::string& name);

// The column's value at a pose: NaN where the pose is not ok (or the stiffness is unbounded).
double column_value(const SweepResult& sweep, const SweepColumn& column, std::size_t pose);

// The pose (index) of a column's worst value among the ok poses, if any has one.
std::optional<std::size_t> worst_pose(const SweepResult& sweep, const SweepColumn& column);

std::string sweep_to_csv(const SweepResult& sweep, bool full);
// `csv_file` is the name the summary gives for the rows (may be empty).
std::string sweep_summary_to_json(const SweepResult& sweep, bool full, const std::string& csv_file);

// ---- Sweeps in blocks: larger than memory, in shards or over MPI ranks --------------------

// The rows of consecutive poses as the output files hold them: the swept parameters' values,
// the status and message, and the value of every column (NaN: an empty cell).
struct SweepRows {
  std::size_t first_pose = 0;  // the first row's pose in the whole sweep
  std::size_t parameter_count = 0;
  std::size_t column_count = 0;
  std::vector<double> parameters;  // row-major, parameter_count per row
  std::vector<PoseStatus> statuses;
  std::vector<std::string> messages;
  // Per row, 1 for an ok pose with deflections beyond the linear method's range
  // (PoseResult::large_deflection): a CSV row tells it by its message.
  std::vector<unsigned char> large_deflections;
  std::vector<double> values;  // row-major, column_count per row

  std::size_t size() const { return statuses.size(); }
  std::span<const double> pose(std::size_t row) const {
    return {parameters.data() + row * parameter_count, parameter_count};
  }
  double value(std::size_t row, std::size_t column) const {
    return values[row * column_count + column];
  }
};

// The rows as bytes and back, for passing between processes of one machine type (MPI ranks).
void serialize_rows(std::string& out, const SweepRows& rows);
SweepRows deserialize_rows(std::string_view bytes);

// The rows of `sweep` (its poses being the whole sweep's from `first_pose` on).
SweepRows sweep_rows(const SweepResult& sweep, const std::vector<SweepColumn>& columns,
                     std::size_t first_pose = 0);

// The CSV's first line, and its rows (sweep_to_csv is the header followed by every row).
std::string sweep_csv_header(const std::vector<std::string>& parameters,
                             const std::vector<SweepColumn>& columns);
void append_sweep_csv_rows(std::string& out, const SweepRows& rows);

// A status from its name in the files ("free-motion").
std::optional<PoseStatus> pose_status_from_string(std::string_view name);

// What the summary reports of a sweep, gathered block by block. Summaries of disjoint blocks
// add up, in any order, to the summary of one pass over all of them: a tie goes to the
// earlier pose.
class SweepSummary {
 public:
  struct Pose {
    std::size_t index = 0;
    std::vector<double> parameters;
    double value = 0;  // a worst pose's value in its column
    PoseStatus status = PoseStatus::ok;
    std::string message;  // a failed pose's
  };

  explicit SweepSummary(std::vector<SweepColumn> columns);
  void add(const SweepRows& rows);
  void add(const SweepSummary& other);

  const std::vector<SweepColumn>& columns() const { return columns_; }
  std::size_t poses() const { return poses_; }
  std::size_t count(PoseStatus status) const { return counts_[static_cast<std::size_t>(status)]; }
  const std::optional<Pose>& worst(std::size_t column) const { return worst_[column]; }
  const std::optional<Pose>& first_failed() const { return first_failed_; }
  // Ok poses with deflections beyond the linear method's range, and the first of them.
  std::size_t large_deflections() const { return large_deflections_; }
  const std::optional<Pose>& first_large_deflection() const { return first_large_deflection_; }

  // For passing between processes: the state as numbers and text, and back.
  std::string serialize() const;
  static SweepSummary deserialize(std::vector<SweepColumn> columns, std::string_view bytes);

 private:
  void offer_worst(std::size_t column, Pose candidate);
  static void offer_first(std::optional<Pose>& first, Pose candidate);

  std::vector<SweepColumn> columns_;
  std::size_t poses_ = 0;
  std::array<std::size_t, kPoseStatuses.size()> counts_{};  // by PoseStatus
  std::vector<std::optional<Pose>> worst_;
  std::optional<Pose> first_failed_;
  std::size_t large_deflections_ = 0;
  std::optional<Pose> first_large_deflection_;
};

// The rows of a sweep CSV as the sweep command writes them, read block by block (to join the
// parts of a sharded sweep). Throws IoError when the file cannot be read and InputError
// (file:line, column) for a header or a line that is not a row of these columns.
class SweepCsvReader {
 public:
  SweepCsvReader(const std::filesystem::path& file, std::vector<std::string> parameters,
                 std::vector<SweepColumn> columns);
  // Up to `count` rows, the first being pose `first_pose`; fewer at the end of the file.
  SweepRows read(std::size_t first_pose, std::size_t count);
  std::size_t rows_read() const { return rows_read_; }

 private:
  bool next_record(std::string& record);

  std::string name_;
  std::ifstream in_;
  std::vector<std::string> parameters_;
  std::vector<SweepColumn> columns_;
  std::size_t line_ = 0;
  std::size_t rows_read_ = 0;
};

// Whether `a` is worse than `b` in `column` (by magnitude for matrix entries); NaN never is.
bool is_worse(const SweepColumn& column, double a, double b);

// The summary JSON of a sweep described by `run` (model, swept parameters, units, grid, end
// effectors, fixed parameters, direction, warnings, threads, seconds; its results are not read).
// Pose indices are the whole sweep's; CSV lines count from `csv_first_pose`, the first pose of the
// file the summary sits beside.
std::string sweep_summary_to_json(const SweepResult& run, bool full, const SweepSummary& summary,
                                  const std::string& csv_file, std::size_t csv_first_pose = 0);

// Whole-or-nothing writes of the two files.
void write_sweep_csv(const SweepResult& sweep, bool full, const std::filesystem::path& file);
void write_sweep_summary(const SweepResult& sweep, bool full, const std::string& csv_file,
                         const std::filesystem::path& file);

}  // namespace stiffmsa
