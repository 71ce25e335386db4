#pragma once
// Sweep files: the poses a user lists (CSV in), one result row per pose (CSV out) and a JSON
// summary naming the worst pose of every column (docs/model-format.md, "Sweep files").
#include <cstddef>
#include <filesystem>
#include <optional>
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
  k_trans_min, k_trans_max, k_rot_min, k_rot_max, deflection_trans, deflection_rot,
  compliance, stiffness, cond_trans, k_trans_dir, k_rot_dir,
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

// Whole-or-nothing writes of the two files.
void write_sweep_csv(const SweepResult& sweep, bool full, const std::filesystem::path& file);
void write_sweep_summary(const SweepResult& sweep, bool full, const std::string& csv_file,
                         const std::filesystem::path& file);

}  // namespace stiffmsa
