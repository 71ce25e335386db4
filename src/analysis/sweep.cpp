#include "stiffmsa/sweep.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <new>
#include <optional>
#include <set>

#include "analysis/critical_load.hpp"
#include "analysis/sweep_row.hpp"
#include "stiffmsa/number_text.hpp"
#include "stiffmsa/validate.hpp"

namespace stiffmsa {

double GridAxis::value(std::size_t i) const {
  if (count <= 1) return start;
  if (i + 1 == count) return stop;  // exactly the stop the user wrote
  const double interpolated =
      start + (stop - start) * static_cast<double>(i) / static_cast<double>(count - 1);
  // The rounding of the interpolation: of the start, of the step times i, and of their sum.
  const double round_off =
      std::numeric_limits<double>::epsilon() *
      (std::abs(start) + std::abs(interpolated - start) + std::abs(interpolated));
  return shortest_decimal_near(interpolated, round_off);
}

PoseTable grid_poses(std::vector<GridAxis> axes, std::size_t max_poses) {
  PoseTable table;
  std::set<std::string> seen;
  std::size_t poses = 1;
  for (const auto& axis : axes) {
    if (axis.count == 0)
      throw UsageError("the grid of '" + axis.parameter +
                       "' has no values; give a count of at least 1");
    if (!std::isfinite(axis.start) || !std::isfinite(axis.stop))
      throw UsageError("the grid of '" + axis.parameter + "' must start and stop at finite values");
    if (!seen.insert(axis.parameter).second)
      throw UsageError("the parameter '" + axis.parameter + "' is swept twice; give each one grid");
    if (poses > max_poses / axis.count)
      throw UsageError("the grid has more than " + std::to_string(max_poses) +
                       " poses; sweep fewer values per parameter");
    poses *= axis.count;
    table.parameters.push_back(axis.parameter);
  }
  if (axes.empty()) return table;
  table = grid_pose_block(axes, 0, poses);
  table.grid = std::move(axes);
  return table;
}

PoseTable grid_pose_block(const std::vector<GridAxis>& axes, std::size_t first, std::size_t count) {
  PoseTable table;
  for (const auto& axis : axes) table.parameters.push_back(axis.parameter);
  table.values.resize(count * axes.size());
  for (std::size_t row = 0; row < count; ++row) {
    std::size_t rest = first + row;
    for (std::size_t k = 0; k < axes.size(); ++k) {
      table.values[row * axes.size() + k] = axes[k].value(rest % axes[k].count);
      rest /= axes[k].count;
    }
  }
  return table;
}

const char* to_string(PoseStatus status) {
  switch (status) {
    case PoseStatus::ok: return "ok";
    case PoseStatus::singular: return "singular";
    case PoseStatus::free_motion: return "free-motion";
    case PoseStatus::invalid: return "invalid";
    case PoseStatus::inaccurate: return "inaccurate";
    case PoseStatus::error: return "error";
  }
  return "?";
}

namespace {

// The first defect with its key, and how many more there are: a CSV cell holds one line.
std::string one_line(const InputError& e) {
  const auto& all = e.diagnostics();
  if (all.empty()) return e.what();
  const Diagnostic& first = all.front();
  std::string text = first.key_path.empty() ? first.message : first.key_path + ": " + first.message;
  if (all.size() > 1) text += " (and " + std::to_string(all.size() - 1) + " more)";
  return text;
}

std::string one_line(const SingularModelError& e) {
  std::string text = e.summary();
  if (!e.details().empty()) text += "; " + e.details().front();
  return text;
}

// What the sweep keeps of a solve; `member_warnings`, the member's reader's, come first among
// the solve's warnings.
PoseResult measure(const Result& result, const std::vector<Diagnostic>& member_warnings,
                   const SweepOptions& options) {
  PoseResult pose;
  if (!result.report.usable()) {
    pose.status = PoseStatus::inaccurate;
    pose.message = result.report.failed_checks.front();
    return pose;
  }
  for (const auto& effector : result.end_effectors) {
    if (effector.compliance) continue;
    pose.status = PoseStatus::free_motion;
    pose.message = "the end effector '" + effector.name + "' can move without load at this pose";
    return pose;
  }
  pose.large_deflection = !result.report.large_deflection.empty();
  if (pose.large_deflection)
    pose.message = result.report.large_deflection;
  else if (!member_warnings.empty())
    pose.message = member_warnings.front().to_string();
  else if (!result.report.warnings.empty())
    pose.message = result.report.warnings.front();
  for (const auto& effector : result.end_effectors) {
    EndEffectorMeasures m;
    m.principal = principal_stiffness(*effector.compliance);
    const Vec6 deflection =
        effector.deflection.value_or(Vec6::Constant(std::numeric_limits<double>::quiet_NaN()));
    m.deflection_translation = deflection.head<3>().norm();
    m.deflection_rotation = deflection.tail<3>().norm();
    m.along_direction = effector.along_direction;
    if (options.keep_matrices) {
      m.compliance = effector.compliance;
      m.stiffness = effector.stiffness;
    }
    pose.end_effectors.push_back(std::move(m));
  }
  return pose;
}

// Classifies what a pose threw into its status; rethrows what is not the pose's fault.
// `built`: the pose's values were written, so what failed is the solve, not the member.
PoseResult failed_pose(std::exception_ptr thrown, bool built) {
  PoseResult pose;
  try {
    std::rethrow_exception(thrown);
  } catch (const InputError& e) {
    pose.status = PoseStatus::invalid;
    pose.message = one_line(e);
  } catch (const SingularModelError& e) {
    pose.status = e.cause() == SingularModelError::Cause::free_motion ? PoseStatus::free_motion
                                                                      : PoseStatus::singular;
    pose.message = one_line(e);
  } catch (const Error& e) {
    // Not the pose's values (those are InputError, SingularModelError or a failed accuracy
    // check): a factorisation or a step of the library that failed.
    pose.status = PoseStatus::error;
    pose.message = e.what();
  } catch (const std::bad_alloc&) {
    throw;  // not the pose's fault: the sweep as a whole cannot go on
  } catch (const std::exception& e) {
    // A caller's family may throw anything; the pose fails, the sweep goes on.
    pose.status = built ? PoseStatus::error : PoseStatus::invalid;
    pose.message =
        std::string(built ? "the solve failed: " : "the model could not be built: ") + e.what();
  }
  return pose;
}

// One thread's share of a sweep: its workspace, the values of its pose, and how it writes them.
struct Worker {
  Workspace workspace;
  std::vector<double> values;
  std::vector<Diagnostic> warnings;  // the member's reader's, from the writer
  // Writes pose i's values and warnings.
  std::function<void(std::size_t, std::span<double>, std::vector<Diagnostic>&)> write;
};

// SweepOptions::load_case names one of the model's load cases.
void check_load_case(const Model& model, const std::string& name) {
  if (name.empty()) return;
  std::string cases;
  for (const LoadCase& c : model.load_cases) {
    if (c.name == name) return;
    cases += (cases.empty() ? "'" : ", '") + c.name + "'";
  }
  throw UsageError(
      "SweepOptions::load_case '" + name + "': the model has no load case of that name (" +
      (cases.empty() ? std::string("it names no load case") : "its cases: " + cases) + ")");
}

// Writes, solves and measures one pose; every failure that belongs to the pose becomes its
// status.
PoseResult solve_one(Worker& worker, std::size_t pose, const SweepOptions& options) {
  bool built = false;
  try {
    worker.write(pose, worker.values, worker.warnings);
    built = true;
    const Result solved = detail::solve_sweep_row(worker.workspace, worker.values, options.solve);
    return measure(options.load_case.empty() ? solved : solved.load_case_result(options.load_case),
                   worker.warnings, options);
  } catch (...) {
    return failed_pose(std::current_exception(), built);
  }
}

// The sweep of one structure over `count` poses, each thread writing its poses' values with
// the writer `make_write` makes for it.
using MakeWrite =
    std::function<std::function<void(std::size_t, std::span<double>, std::vector<Diagnostic>&)>()>;
std::vector<PoseResult> run_poses(const Structure& structure, std::size_t count,
                                  const MakeWrite& make_write, const SweepOptions& options,
                                  std::size_t& threads_used, double& seconds) {
  // The workspace built here goes to the first thread, so a one-thread sweep analyses the
  // topology once.
  std::optional<Workspace> first_workspace(std::in_place, structure);
  std::mutex first_workspace_lock;
  const auto take_workspace = [&] {
    std::lock_guard lock(first_workspace_lock);
    if (!first_workspace) return Workspace(structure);
    Workspace taken = std::move(*first_workspace);
    first_workspace.reset();
    return taken;
  };
  std::vector<PoseResult> results(count);

  // More threads than this only queue for the same cores.
  constexpr std::size_t max_threads = 1024;
  const std::size_t threads = std::min(
      max_threads, options.threads == 0 ? static_cast<std::size_t>(tbb::info::default_concurrency())
                                        : options.threads);
  // A pose's result keeps no critical load factor (PoseResult has none): its workspace skips
  // finding one, which the loaded mode's results would otherwise find unasked.
  tbb::enumerable_thread_specific<Worker> workers([&] {
    Worker worker{take_workspace(), std::vector<double>(structure.value_count()), {}, make_write()};
    detail::skip_critical_loads(worker.workspace);
    return worker;
  });

  std::atomic<std::size_t> done{0};
  std::mutex progress_lock;
  const auto report_progress = [&](std::size_t finished) {
    if (!options.progress) return;
    std::unique_lock lock(progress_lock, std::try_to_lock);
    if (lock.owns_lock()) options.progress(finished, count);
  };

  const auto start = std::chrono::steady_clock::now();
  tbb::task_arena arena(static_cast<int>(threads));
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        Worker& worker = workers.local();
                        for (std::size_t i = range.begin(); i != range.end(); ++i)
                          results[i] = solve_one(worker, i, options);
                        report_progress(done += range.size());
                      });
  });
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  threads_used = std::max<std::size_t>(1, workers.size());  // the threads that took part
  if (options.progress) {
    std::lock_guard lock(progress_lock);
    options.progress(count, count);
  }
  return results;
}

// The full values of every parameter at one pose: defaults, with the swept ones replaced.
struct PoseValues {
  std::vector<double> all;
  std::vector<std::size_t> swept;  // index in `all` of each swept parameter

  void set(std::span<const double> pose) {
    for (std::size_t k = 0; k < swept.size(); ++k) all[swept[k]] = pose[k];
  }
};

PoseValues pose_values(const ModelFamily& family, const PoseTable& poses) {
  PoseValues values{family.default_values(), {}};
  for (const auto& name : poses.parameters) values.swept.push_back(family.parameter_index(name));
  return values;
}

}  // namespace

std::vector<PoseResult> solve_poses(const Structure& structure, std::span<const double> value_sets,
                                    const SweepOptions& options) {
  options.solve.validate();
  check_load_case(structure.model(), options.load_case);
  const std::size_t slots = structure.value_count();
  if (slots == 0 ? !value_sets.empty() : value_sets.size() % slots != 0)
    throw UsageError("the value sets hold " + std::to_string(value_sets.size()) +
                     " values, not a multiple of the " + std::to_string(slots) +
                     " value slots of the structure");
  const std::size_t count = slots == 0 ? 0 : value_sets.size() / slots;
  const MakeWrite make_write = [&] {
    return [&](std::size_t pose, std::span<double> values, std::vector<Diagnostic>&) {
      const auto row = value_sets.subspan(pose * slots, slots);
      std::copy(row.begin(), row.end(), values.begin());
    };
  };
  std::size_t threads = 0;
  double seconds = 0;
  return run_poses(structure, count, make_write, options, threads, seconds);
}

SweepResult sweep(const ModelFamily& family, const PoseTable& poses, const SweepOptions& options) {
  options.solve.validate();
  const PoseValues defaults = pose_values(family, poses);
  // The defaults' own defects are the caller's error, not a pose's: they throw here. The
  // member at the defaults is every workspace's reference pose.
  const Model reference = family.build(defaults.all);
  check_load_case(reference, options.load_case);
  const Structure family_structure = family.structure();
  const Structure structure =
      family_structure.with_default_values(family_structure.values_of(reference));

  SweepResult sweep_result;
  sweep_result.model = reference.name;
  sweep_result.poses = poses;
  for (std::size_t index : defaults.swept)
    sweep_result.units.push_back(family.parameters()[index].unit);
  for (const auto& e : reference.end_effectors) sweep_result.end_effectors.push_back(e.name);
  const std::vector<ParameterValue> all_parameters = family.parameter_values();
  for (std::size_t i = 0; i < all_parameters.size(); ++i)
    if (std::find(defaults.swept.begin(), defaults.swept.end(), i) == defaults.swept.end())
      sweep_result.fixed_parameters.push_back(all_parameters[i]);
  if (options.solve.direction) sweep_result.direction = options.solve.direction->normalized();
  for (const Diagnostic& d : find_implausible_values(reference))
    sweep_result.warnings.push_back(d.to_string());

  const MakeWrite make_write = [&] {
    return
        [write = family.make_writer(family_structure), parameters = defaults, &poses](
            std::size_t pose, std::span<double> values, std::vector<Diagnostic>& warnings) mutable {
          parameters.set(poses.pose(pose));
          write(parameters.all, values, warnings);
        };
  };
  sweep_result.results = run_poses(structure, poses.size(), make_write, options,
                                   sweep_result.threads, sweep_result.seconds);
  return sweep_result;
}

}  // namespace stiffmsa
