#pragma once
// Sweeps: the stiffness of a model family (parametric.hpp) at many poses, for stiffness maps.
// Every pose is built, solved and measured on its own; a pose that fails gets a status and a
// message and the sweep goes on. Poses are spread over threads; the result does not depend on
// how many or in which order they run.
#include <array>
#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "stiffmsa/analysis.hpp"
#include "stiffmsa/parametric.hpp"

namespace stiffmsa {

// `count` evenly spaced values from `start` to `stop`, both included (count 1: start alone);
// each is the shortest decimal within rounding of its place where there is one (0.11, not
// 0.11000000000000001), so that rows and labels read as the grid was written.
struct GridAxis {
  std::string parameter;
  double start = 0;
  double stop = 0;
  std::size_t count = 0;

  double value(std::size_t i) const;
};

// The poses of a sweep: values of the swept parameters, one row per pose. The other
// parameters keep their defaults.
struct PoseTable {
  std::vector<std::string> parameters;
  std::vector<double> values;  // row-major: values[pose * parameters.size() + k]
  // For a grid, the axes; the first axis varies fastest (pose = i0 + n0 * (i1 + n1 * ...)).
  std::vector<GridAxis> grid;

  std::size_t size() const { return parameters.empty() ? 0 : values.size() / parameters.size(); }
  std::span<const double> pose(std::size_t i) const {
    return {values.data() + i * parameters.size(), parameters.size()};
  }
};

// Every combination of the axes' values. Throws UsageError for an empty axis, a repeated
// parameter or a grid of more than `max_poses` poses.
PoseTable grid_poses(std::vector<GridAxis> axes, std::size_t max_poses = 10'000'000);

// The poses `first` … `first + count - 1` of the grid of `axes` (in grid_poses' order), without
// `grid`: a block of a sweep too large to hold at once. The axes are not checked here.
PoseTable grid_pose_block(const std::vector<GridAxis>& axes, std::size_t first, std::size_t count);

// In the order of their codes in a sweep file (docs/sweeps.md): new ones come last.
enum class PoseStatus {
  ok,           // every end effector's compliance is determined
  singular,     // the system is singular to working precision
  free_motion,  // an end effector (or the structure) can move without load at this pose
  invalid,      // the parameter values make an invalid model (message says which key)
  inaccurate,   // solved, but an accuracy check failed (SolveReport::usable() is false)
  error,        // the solve failed otherwise: an internal error, not the pose's values
};
inline constexpr std::array kPoseStatuses{PoseStatus::ok,          PoseStatus::singular,
                                          PoseStatus::free_motion, PoseStatus::invalid,
                                          PoseStatus::inaccurate,  PoseStatus::error};
// "ok", "singular", "free-motion", "invalid", "inaccurate", "error"
const char* to_string(PoseStatus status);

// What a sweep reports of one end effector at one pose.
struct EndEffectorMeasures {
  PrincipalStiffness principal;       // +inf where a block is singular (a rigidly held direction)
  double deflection_translation = 0;  // |Δp| under the model's loads
  double deflection_rotation = 0;     // |Δφ|
  // With SolveOptions::direction: the stiffness along it (+inf where held rigidly).
  std::optional<DirectionalStiffness> along_direction;
  std::optional<Mat6> compliance;  // kept with SweepOptions::keep_matrices
  std::optional<Mat6> stiffness;   // kept with keep_matrices; nullopt where unbounded
};

struct PoseResult {
  PoseStatus status = PoseStatus::ok;
  // Why the pose failed; for an ok pose, the warning of large deflections if there is one,
  // else the solve's first warning, if any.
  std::string message;
  // An ok pose whose deflections under the loads are beyond the linear method's range
  // (SolveReport::large_deflection): its numbers are kept, to be read with care.
  bool large_deflection = false;
  std::vector<EndEffectorMeasures> end_effectors;  // model order; empty unless ok
};

struct SweepOptions {
  SolveOptions solve;
  bool keep_matrices = false;
  std::size_t threads = 0;  // 0: every core
  // Called now and then with (poses done, poses in all), never from two threads at once.
  std::function<void(std::size_t, std::size_t)> progress;
  // The named load case whose results each pose's row takes (`sweep --case`); empty: the
  // top-level results (the unnamed case, or the first named one). A name the model does not
  // have is a UsageError listing its cases.
  std::string load_case;
};

struct SweepResult {
  std::string model;
  PoseTable poses;
  std::vector<std::string> units;  // of the swept parameters, as the family gives them
  std::vector<std::string> end_effectors;
  // The parameters the sweep does not vary, at the values every pose has.
  std::vector<ParameterValue> fixed_parameters;
  // The unit direction of SweepOptions::solve.direction, if given.
  std::optional<Vec3> direction;
  // find_implausible_values() of the model at the defaults, each as Diagnostic::to_string().
  std::vector<std::string> warnings;
  std::vector<PoseResult> results;  // one per pose, in pose order
  std::size_t threads = 1;          // threads that solved poses (at most SweepOptions::threads)
  double seconds = 0;               // wall time of the solves
};

// The core of a sweep: a structure solved at many sets of values, `value_sets` holding
// structure.value_count() values per pose (row-major), each pose solved and measured as
// sweep() does (its status and message; a pose whose values fail their checks is invalid).
// The first pose's index is 0; `progress` and `threads` as in SweepOptions.
std::vector<PoseResult> solve_poses(const Structure& structure, std::span<const double> value_sets,
                                    const SweepOptions& options = {});

// Solves the family at each pose: its structure, and at each pose the values its writer writes
// for the pose's parameter values (the defaults for the parameters not swept). A pose whose
// values fail their checks, or whose member (a function family's) has another structure, is
// invalid, with a message saying so. Throws InputError when the defaults themselves give an invalid
// model and UsageError when a swept name is not a parameter.
SweepResult sweep(const ModelFamily& family, const PoseTable& poses,
                  const SweepOptions& options = {});

}  // namespace stiffmsa
