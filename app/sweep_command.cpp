#include "sweep_command.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "stiffmsa/config.hpp"
#include "stiffmsa/number_text.hpp"
#include "summary.hpp"
#include "sweep_output.hpp"
#if STIFFMSA_CLI_MPI
#include "sweep_mpi.hpp"
#endif

namespace stiffmsa::cli {

namespace {

namespace fs = std::filesystem;

// More poses than a sweep's index can count, with room to spare (a billion poses is 10⁹).
constexpr std::size_t kMaxPoses = 1'000'000'000'000'000;

// "name=start:stop:count"
GridAxis parse_grid(const std::string& spec) {
  const auto usage = [&](const std::string& what) {
    return UsageError("--grid '" + spec + "': " + what +
                      "; write NAME=START:STOP:COUNT, e.g. x=-0.2:0.2:41");
  };
  const auto equals = spec.find('=');
  if (equals == std::string::npos || equals == 0) throw usage("no parameter name before '='");
  GridAxis axis;
  axis.parameter = spec.substr(0, equals);
  const std::string range = spec.substr(equals + 1);
  const auto colon1 = range.find(':');
  const auto colon2 = colon1 == std::string::npos ? std::string::npos : range.find(':', colon1 + 1);
  if (colon2 == std::string::npos || range.find(':', colon2 + 1) != std::string::npos)
    throw usage("expected three values separated by ':'");
  const auto start = parse_plain_number(range.substr(0, colon1));
  const auto stop = parse_plain_number(range.substr(colon1 + 1, colon2 - colon1 - 1));
  if (!start || !stop) throw usage("START and STOP must be finite numbers");
  const std::string count_text = range.substr(colon2 + 1);
  std::size_t count = 0;
  const auto [end, error] =
      std::from_chars(count_text.data(), count_text.data() + count_text.size(), count);
  if (count_text.empty() || error != std::errc() || end != count_text.data() + count_text.size() ||
      count == 0)
    throw usage("COUNT must be a whole number of at least 1");
  axis.start = *start;
  axis.stop = *stop;
  axis.count = count;
  return axis;
}

// Output files must not be inputs or each other, and their folder must exist: checked before
// the sweep, so that a long sweep does not end in an error that writes nothing.
struct OutputFile {
  fs::path path;
  std::string option;  // "--csv"
  std::string noun;    // "the CSV"
};

void check_files(const SweepCommand& command, const std::vector<OutputFile>& outputs) {
  std::vector<std::pair<fs::path, std::string>> inputs{{command.model_file, "the model file"}};
  if (!command.poses_file.empty()) inputs.emplace_back(command.poses_file, "the pose file");
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const auto& [output, option, noun] = outputs[i];
    for (const auto& [input, what] : inputs)
      if (same_file(output, input))
        throw UsageError(option + " '" + output.string() + "' is " + what +
                         "; choose another name");
    for (std::size_t j = 0; j < i; ++j)
      if (same_file(output, outputs[j].path))
        throw UsageError(noun + " '" + output.string() + "' would replace " + outputs[j].noun +
                         "; choose another name for " + option);
    const fs::path folder = output.parent_path().empty() ? fs::path(".") : output.parent_path();
    std::error_code error;
    if (!fs::is_directory(folder, error))
      throw UsageError(option + " '" + output.string() + "': the folder '" + folder.string() +
                       "' does not exist");
  }
}

// "K/N": the K-th (from 1) of N parts.
std::pair<std::size_t, std::size_t> parse_shard(const std::string& spec) {
  const auto slash = spec.find('/');
  std::size_t part = 0, parts = 0;
  const auto whole = [](std::string_view text, std::size_t& value) {
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    return !text.empty() && error == std::errc() && end == text.data() + text.size();
  };
  if (slash == std::string::npos || !whole(std::string_view(spec).substr(0, slash), part) ||
      !whole(std::string_view(spec).substr(slash + 1), parts) || parts == 0 || part == 0 ||
      part > parts)
    throw UsageError("--shard '" + spec +
                     "': write K/N with 1 <= K <= N, e.g. 3/8 for the third of eight parts");
  return {part, parts};
}

// FNV-1a: tells a part of one sweep from a part of another (not a guard against forgery).
std::string fingerprint(std::string_view bytes) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (unsigned char c : bytes) {
    hash ^= c;
    hash *= 0x100000001b3ULL;
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

std::string file_fingerprint(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) throw IoError("cannot read " + what + " '" + path + "'");
  return fingerprint(text.str());
}

// What must be the same for parts to make one sweep: this program, the model file, the values
// set, the poses, the columns and the solver (docs/cluster.md, "Shards").
nlohmann::json sweep_identity(const SweepCommand& command, const std::vector<GridAxis>& axes,
                              std::size_t poses) {
  nlohmann::json identity;
  identity["stiffmsa"] = STIFFMSA_VERSION;
  identity["model_file"] = file_fingerprint(command.model_file, "the model file");
  nlohmann::json settings = nlohmann::json::object();
  for (const auto& [name, value] : parse_settings(command.settings))
    settings[name] = shortest_text(value);
  identity["set"] = std::move(settings);
  if (command.poses_file.empty()) {
    nlohmann::json grid = nlohmann::json::array();
    for (const auto& axis : axes)
      grid.push_back(axis.parameter + "=" + shortest_text(axis.start) + ":" +
                     shortest_text(axis.stop) + ":" + std::to_string(axis.count));
    identity["grid"] = std::move(grid);
  } else {
    identity["pose_file"] = file_fingerprint(command.poses_file, "the pose file");
  }
  identity["poses"] = poses;
  identity["full"] = command.full;
  identity["solver"] = to_string(command.solve.solver);
  if (command.solve.direction)
    identity["direction"] = {(*command.solve.direction)(0), (*command.solve.direction)(1),
                             (*command.solve.direction)(2)};
  identity["accept_idle_motions"] = command.solve.accept_idle_motions;
  if (command.solve.mode) identity["mode"] = to_string(*command.solve.mode);
  return identity;
}

// The number of poses of a grid, refused when it would not fit in memory's index range.
std::size_t grid_size(const std::vector<GridAxis>& axes) {
  std::size_t poses = 1;
  for (const auto& axis : axes) {
    if (axis.count > kMaxPoses / poses)
      throw UsageError("the grid has more than " + std::to_string(kMaxPoses) +
                       " poses; sweep fewer values per parameter");
    poses *= axis.count;
  }
  return poses;
}

}  // namespace

Vec3 parse_direction(const std::string& text) {
  Vec3 direction = Vec3::Zero();
  std::size_t start = 0;
  int count = 0;
  bool numbers = true;
  for (; start <= text.size(); ++count) {
    const auto comma = std::min(text.find(',', start), text.size());
    const auto value = parse_plain_number(std::string_view(text).substr(start, comma - start));
    numbers = numbers && value && count < 3;
    if (numbers) direction(count) = *value;
    start = comma + 1;
  }
  if (!numbers || count != 3)
    throw UsageError("--direction '" + text + "': write X,Y,Z, three finite numbers, e.g. 0,0,1");
  if (direction.isZero(0))
    throw UsageError("--direction '" + text + "': the direction must not be zero");
  return direction;
}

bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code a_error, b_error;
  const fs::path first = fs::weakly_canonical(a, a_error);
  const fs::path second = fs::weakly_canonical(b, b_error);
  return !a_error && !b_error && first == second;
}

ParameterSettings parse_settings(const std::vector<std::string>& settings) {
  ParameterSettings parsed;
  for (const auto& setting : settings) {
    const auto equals = setting.find('=');
    const auto value = equals == std::string::npos || equals == 0
                           ? std::nullopt
                           : parse_plain_number(std::string_view(setting).substr(equals + 1));
    if (!value)
      throw UsageError("--set '" + setting +
                       "': write NAME=VALUE with a finite number, e.g. x=0.1");
    if (!parsed.emplace(setting.substr(0, equals), *value).second)
      throw UsageError("--set '" + setting + "': the parameter is set twice");
  }
  return parsed;
}

SweepResult SweepPlan::solve(std::size_t first, std::size_t count,
                             const std::function<void(std::size_t, std::size_t)>& progress) const {
  SweepOptions block_options = options;
  block_options.progress = progress;
  if (!axes.empty()) return sweep(*family, grid_pose_block(axes, first, count), block_options);
  PoseTable block;
  block.parameters = listed->parameters;
  const std::size_t width = listed->parameters.size();
  block.values.assign(
      listed->values.begin() + static_cast<std::ptrdiff_t>(first * width),
      listed->values.begin() + static_cast<std::ptrdiff_t>((first + count) * width));
  return sweep(*family, block, block_options);
}

std::unique_ptr<PreparedSweep> prepare_sweep(const SweepCommand& command) {
  if (command.grids.empty() == command.poses_file.empty())
    throw UsageError(
        "give the poses either as --grid NAME=START:STOP:COUNT (one per swept parameter) or as "
        "--poses FILE.csv");
  if (command.csv_file.empty() && command.hdf5_file.empty())
    throw UsageError("give an output for the rows: --csv FILE.csv, --hdf5 FILE.h5, or both");
  auto owned = std::make_unique<PreparedSweep>();
  PreparedSweep& prepared = *owned;
  for (const auto& spec : command.grids) prepared.axes.push_back(parse_grid(spec));
  std::optional<std::pair<std::size_t, std::size_t>> shard;
  if (!command.shard.empty()) {
    shard = parse_shard(command.shard);
    if (command.plot)
      throw UsageError(
          "--plot with --shard: a part holds only some of the poses; draw the plots when merging "
          "(stiffmsa merge OUT.csv PART... --plot)");
    if (command.view)
      throw UsageError(
          "--view with --shard: a part holds only some of the poses; the map is of a whole sweep "
          "run in one process");
  }
  if (command.plot) check_plot_grid(prepared.axes, !command.poses_file.empty());
  if (!command.grids.empty()) {
    // grid_poses' own checks (empty axes, repeated names) on a grid of one pose per axis.
    std::vector<GridAxis> probe = prepared.axes;
    for (auto& axis : probe) axis.count = std::min<std::size_t>(axis.count, 1);
    (void)grid_poses(probe);
  }
  const fs::path rows_file(command.csv_file.empty() ? command.hdf5_file : command.csv_file);
  prepared.files.csv = command.csv_file;
  prepared.files.hdf5 = command.hdf5_file;
  prepared.files.summary =
      command.summary_file.empty()
          ? rows_file.parent_path() / (rows_file.stem().string() + ".summary.json")
          : fs::path(command.summary_file);
  prepared.files.plot_base = rows_file.parent_path() / rows_file.stem();
  std::vector<OutputFile> outputs;
  if (!command.csv_file.empty()) outputs.push_back({command.csv_file, "--csv", "the CSV"});
  if (!command.hdf5_file.empty()) outputs.push_back({command.hdf5_file, "--hdf5", "the HDF5 file"});
  outputs.push_back({prepared.files.summary, "--summary", "the summary"});
  if (command.view) {
    prepared.view_file = rows_file.parent_path() / (rows_file.stem().string() + ".html");
    outputs.push_back({prepared.view_file, "--view", "the view map"});
  }
  check_files(command, outputs);
#if !STIFFMSA_CLI_HDF5
  if (!command.hdf5_file.empty())
    throw UsageError(
        "--hdf5: this build of stiffmsa writes no HDF5 (built without HDF5); write --csv");
#endif

  prepared.family.emplace(
      load_model_family(command.model_file, command.limits, parse_settings(command.settings)));
  std::size_t poses = 0;
  if (command.poses_file.empty()) {
    poses = grid_size(prepared.axes);
  } else {
    prepared.listed = read_pose_table(command.poses_file);
    poses = prepared.listed.size();
  }

  // What the summary says of the sweep: the rows' columns come from the model at the defaults.
  SweepDescription& description = prepared.description;
  const Model reference = prepared.family->build(prepared.family->default_values());
  description.run.model = reference.name;
  for (const auto& e : reference.end_effectors) description.run.end_effectors.push_back(e.name);
  description.run.poses.parameters =
      command.poses_file.empty() ? std::vector<std::string>{} : prepared.listed.parameters;
  for (const auto& axis : prepared.axes) description.run.poses.parameters.push_back(axis.parameter);
  description.run.poses.grid = prepared.axes;
  if (command.solve.direction) description.run.direction = command.solve.direction->normalized();
  description.loads = loads_text(reference);
  if (!command.load_case.empty()) {
    const auto chosen =
        std::find_if(reference.load_cases.begin(), reference.load_cases.end(),
                     [&](const LoadCase& c) { return c.name == command.load_case; });
    if (chosen == reference.load_cases.end()) {
      std::string cases;
      for (const LoadCase& c : reference.load_cases)
        cases += (cases.empty() ? "'" : ", '") + c.name + "'";
      throw UsageError(
          "--case '" + command.load_case + "': the model has no load case of that name (" +
          (cases.empty() ? std::string("it names no load case") : "its cases: " + cases) + ")");
    }
    Model case_loads = reference;
    case_loads.loads = chosen->loads;
    description.loads = "load case '" + chosen->name + "': " + loads_text(case_loads);
  }
  for (const auto& name : description.run.poses.parameters) {
    const auto index = prepared.family->find_parameter(name);
    description.run.units.push_back(index ? prepared.family->parameters()[*index].unit : "");
  }
  description.full = command.full;
  description.columns = sweep_columns(description.run, command.full);
  description.poses = poses;

  SweepPlan& plan = prepared.plan;
  plan.family = &*prepared.family;
  plan.axes = prepared.axes;
  plan.listed = &prepared.listed;
  plan.block = command.block;
  plan.options.solve = command.solve;
  plan.options.keep_matrices = command.full;
  plan.options.load_case = command.load_case;
  plan.options.threads = command.threads;
  if (command.plot) {
    prepared.files.plotted = plotted_columns(description.run, command.plot_columns);
    // A matrix entry is kept for its plot even without --full.
    for (const auto& column : prepared.files.plotted)
      if (column.quantity == SweepQuantity::compliance ||
          column.quantity == SweepQuantity::stiffness)
        plan.options.keep_matrices = true;
  }
  plan.first = 0;
  plan.end = poses;
  if (shard) {
    const auto [part, parts] = *shard;
    const auto bound = [&](std::size_t k) {
      return poses / parts * k + poses % parts * k / parts;  // ⌊poses·k/parts⌋ without overflow
    };
    plan.first = bound(part - 1);
    plan.end = bound(part);
    nlohmann::json extra;
    extra["shard"] = {
        {"part", part}, {"parts", parts}, {"first_pose", plan.first}, {"poses_in_all", poses}};
    extra["identity"] = sweep_identity(command, prepared.axes, poses);
    prepared.extra_summary = extra.dump();
  }
  // A swept name that is no parameter is refused before any pose; what a sweep says of the
  // parameters it holds fixed and of the model's plausibility comes with no pose solved.
  const SweepResult none_solved = plan.solve(plan.first, 0);
  description.run.fixed_parameters = none_solved.fixed_parameters;
  description.run.warnings = none_solved.warnings;
  if (shard) {
    // For the plots and lines that merge draws and prints: the loads, and the fixed parameters
    // in the model's order (the summary's object of them is by name).
    auto extra = nlohmann::json::parse(prepared.extra_summary);
    extra["loads"] = description.loads;
    nlohmann::json fixed_order = nlohmann::json::array();
    for (const auto& p : description.run.fixed_parameters) fixed_order.push_back(p.name);
    extra["fixed_parameter_order"] = std::move(fixed_order);
    prepared.extra_summary = extra.dump();
  }
  if (command.view && poses > kMaxPosesInMemory)
    throw UsageError("--view: the sweep has " + std::to_string(poses) +
                     " poses; a view map holds every pose's "
                     "result in memory and is written of at most " +
                     std::to_string(kMaxPosesInMemory));
  return owned;
}

int run_sweep(const SweepCommand& command) {
#if STIFFMSA_CLI_MPI
  if (started_by_mpi_launcher()) return run_sweep_over_ranks(command);
#endif
  const auto owned = prepare_sweep(command);
  const PreparedSweep& prepared = *owned;
  const SweepPlan& plan = prepared.plan;
  SweepOutput output(prepared.description, prepared.files, plan.first, plan.end - plan.first);

  ProgressBar bar(!command.quiet);
  const std::size_t poses = plan.end - plan.first;
  SweepResult viewed = prepared.description.run;  // with --view: every pose's result
  std::size_t threads = 1;
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t first = plan.first; first < plan.end; first += plan.block) {
    const std::size_t count = std::min(plan.block, plan.end - first);
    const std::size_t done = first - plan.first;
    const SweepResult solved = plan.solve(first, count, [&](std::size_t in_block, std::size_t) {
      bar.update(done + in_block, poses);
    });
    output.write(make_block(output.shape(), solved, first));
    threads = std::max(threads, solved.threads);
    if (command.view) {
      // The map shows every pose: the only output that holds the whole sweep in memory.
      viewed.poses.values.insert(viewed.poses.values.end(), solved.poses.values.begin(),
                                 solved.poses.values.end());
      viewed.results.insert(viewed.results.end(), solved.results.begin(), solved.results.end());
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  bar.finish();
  auto files = output.finish(threads, seconds, prepared.extra_summary);
  if (command.view) {
    write_sweep_view(viewed, prepared.view_file);
    files.push_back(prepared.view_file);
  }
  print_sweep_summary(std::cout, prepared.description, output.summary(), threads, seconds, files);
  return exit_success;
}

}  // namespace stiffmsa::cli
