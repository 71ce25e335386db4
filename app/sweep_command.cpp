#include "sweep_command.hpp"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "summary.hpp"

namespace stiffmsa::cli {

namespace {

namespace fs = std::filesystem;

std::string comma_separated(const std::vector<std::string>& names) {
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i) text += (i > 0 ? ", " : "") + names[i];
  return text;
}

// "name=start:stop:count"
GridAxis parse_grid(const std::string& spec) {
  const auto usage = [&](const std::string& what) {
    return UsageError("--grid '" + spec + "': " + what + "; write NAME=START:STOP:COUNT, e.g. x=-0.2:0.2:41");
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
  const auto [end, error] = std::from_chars(count_text.data(), count_text.data() + count_text.size(), count);
  if (count_text.empty() || error != std::errc() || end != count_text.data() + count_text.size() || count == 0)
    throw usage("COUNT must be a whole number of at least 1");
  axis.start = *start;
  axis.stop = *stop;
  axis.count = count;
  return axis;
}

std::string with_unit(double value, const std::string& unit) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.4g", value);
  return unit.empty() ? std::string(buffer) : std::string(buffer) + " " + unit;
}

// "x = 0.1 m, y = 0.2 m"
std::string pose_text(const SweepResult& sweep, std::size_t pose) {
  std::string text;
  const auto values = sweep.poses.pose(pose);
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (k > 0) text += ", ";
    text += sweep.poses.parameters[k] + " = " + value_with_unit(values[k], sweep.units[k]);
  }
  return text;
}

// "(0, 0, -100)"
std::string vector_text(const Vec3& v) {
  return "(" + shortest_text(v(0)) + ", " + shortest_text(v(1)) + ", " + shortest_text(v(2)) + ")";
}

// The loads a deflection map is computed under: "F (0, 0, -100) N at E"; at most
// `shown` of them, then how many more.
std::string loads_text(const Model& model) {
  constexpr std::size_t shown = 2;
  std::string text;
  for (std::size_t i = 0; i < model.loads.size() && i < shown; ++i) {
    const Load& load = model.loads[i];
    std::string wrench;
    if (!load.wrench.head<3>().isZero(0)) wrench = "F " + vector_text(load.wrench.head<3>()) + " N";
    if (!load.wrench.tail<3>().isZero(0))
      wrench += (wrench.empty() ? "M " : ", M ") + vector_text(load.wrench.tail<3>()) + " N·m";
    if (wrench.empty()) wrench = "zero wrench";
    text += (i > 0 ? "; " : "") + wrench + " at " + load.at;
  }
  if (model.loads.size() > shown) text += "; and " + counted(model.loads.size() - shown, "more load");
  return text.empty() ? "no loads" : text;
}

// A bar on the terminal, for sweeps long enough to wait for; nothing when stderr is a file.
class ProgressBar {
 public:
  explicit ProgressBar(bool enabled) : enabled_(enabled && ::isatty(STDERR_FILENO) == 1) {}

  void update(std::size_t done, std::size_t total) {
    if (!enabled_ || total == 0) return;
    const double elapsed = seconds_since_start();
    if (elapsed < 1.0 || (done < total && elapsed - last_drawn_ < 0.1)) return;
    last_drawn_ = elapsed;
    constexpr int width = 30;
    const double fraction = static_cast<double>(done) / static_cast<double>(total);
    const int filled = static_cast<int>(fraction * width);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(width, '.');
    std::fprintf(stderr, "\rsweep [%s] %3d%% %zu/%zu poses", bar.c_str(), static_cast<int>(fraction * 100), done,
                 total);
    if (done > 0 && done < total)
      std::fprintf(stderr, ", %.0f s left   ", elapsed * static_cast<double>(total - done) / static_cast<double>(done));
    drawn_ = true;
    std::fflush(stderr);
  }

  // Clears the bar, so that what is printed next starts on a clean line.
  void finish() {
    if (drawn_) std::fprintf(stderr, "\r\033[K");
    drawn_ = false;
  }
  ~ProgressBar() { finish(); }

 private:
  double seconds_since_start() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  bool enabled_;
  bool drawn_ = false;
  double last_drawn_ = 0;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// Stiffness near a singular pose spans decades: a log scale shows the whole map.
PlotScale scale_for(const std::vector<double>& values) {
  double low = INFINITY, high = 0;
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    if (v <= 0) return PlotScale::linear;
    low = std::min(low, v);
    high = std::max(high, v);
  }
  return high > 30 * low ? PlotScale::logarithmic : PlotScale::linear;
}

std::vector<SweepColumn> plotted_columns(const SweepResult& sweep, const SweepCommand& command) {
  std::vector<SweepColumn> columns;
  if (command.plot_columns.empty()) {
    for (const auto& column : sweep_columns(sweep, false))
      if (column.quantity == SweepQuantity::k_trans_min || column.quantity == SweepQuantity::deflection_trans)
        columns.push_back(column);
    return columns;
  }
  for (const auto& name : command.plot_columns) {
    auto column = find_sweep_column(sweep, name);
    if (!column) {
      std::vector<std::string> names;
      for (const auto& c : sweep_columns(sweep, false)) names.push_back(c.name);
      throw UsageError("--plot-column '" + name + "': no such column; columns are " + comma_separated(names) +
                       " and the compliance and stiffness entries E.C11 … E.K66");
    }
    columns.push_back(*column);
  }
  return columns;
}

// Plots of every chosen column, PNG and SVG, named after the CSV: map.csv -> map.E.k_trans_min.png.
// Their subtitles name the parameters held fixed and, on deflection maps, the loads of `model`.
std::vector<fs::path> write_plots(const SweepResult& sweep, const SweepCommand& command, const Model& model) {
  std::vector<fs::path> written;
  const fs::path csv(command.csv_file);
  const fs::path base = csv.parent_path() / csv.stem();
  const auto& grid = sweep.poses.grid;
  for (const auto& column : plotted_columns(sweep, command)) {
    std::vector<double> values(sweep.results.size());
    bool any_failed = false, any_rigid = false;
    for (std::size_t pose = 0; pose < values.size(); ++pose) {
      values[pose] = column_value(sweep, column, pose);
      any_failed = any_failed || std::isnan(values[pose]);
      if (std::isinf(values[pose])) {
        values[pose] = NAN;  // a rigidly held direction has no colour on the scale
        any_rigid = true;
      }
    }
    const std::string no_value = any_rigid ? (any_failed ? "no value: failed pose, or rigid (infinite)"
                                                         : "rigid direction (infinite stiffness)")
                                           : "no value (failed pose)";
    const auto worst = worst_pose(sweep, column);
    const std::string label = worst ? std::string(column.worst_is_largest ? "largest" : "smallest") + ": " +
                                          with_unit(column_value(sweep, column, *worst), column.unit)
                                    : std::string();
    const std::string title = sweep.model + ": " + column.name;
    const bool deflection =
        column.quantity == SweepQuantity::deflection_trans || column.quantity == SweepQuantity::deflection_rot;
    std::string subtitle = sweep.fixed_parameters.empty() ? "" : "at " + parameters_text(sweep.fixed_parameters);
    if (deflection) subtitle += (subtitle.empty() ? "under " : "; under ") + loads_text(model);
    std::vector<bool> flagged;
    for (const auto& r : sweep.results) flagged.push_back(r.large_deflection);
    if (std::find(flagged.begin(), flagged.end(), true) == flagged.end()) flagged.clear();
    const std::string flagged_label = "deflections beyond the linear method's range (large_deflection)";
    const auto axis = [&](std::size_t k) {
      PlotAxis a{grid[k].parameter, sweep.units[k], {}};
      for (std::size_t i = 0; i < grid[k].count; ++i) a.values.push_back(grid[k].value(i));
      return a;
    };
    for (const char* extension : {".png", ".svg"}) {
      const fs::path file = base.string() + "." + column.name + extension;
      if (grid.size() == 1) {
        LinePlot plot{title,    axis(0),  column.name, column.unit, values,       scale_for(values),
                      worst,    label,    no_value,    subtitle,    flagged,      flagged_label};
        write_plot(plot, file);
      } else {
        Heatmap plot{title,    axis(0),  axis(1),  column.name,  column.unit,  values, scale_for(values),
                     std::nullopt, label, no_value, subtitle, flagged, flagged_label};
        if (worst) plot.marked = std::pair{*worst % grid[0].count, *worst / grid[0].count};
        write_plot(plot, file);
      }
      written.push_back(file);
    }
  }
  return written;
}

void print_sweep_summary(std::ostream& out, const SweepResult& sweep, const std::vector<fs::path>& files) {
  const std::size_t poses = sweep.results.size();
  out << "sweep of " << sweep.model << ": " << poses << " poses over ";
  for (std::size_t k = 0; k < sweep.poses.parameters.size(); ++k)
    out << (k > 0 ? ", " : "") << sweep.poses.parameters[k];
  char rate[96];
  std::snprintf(rate, sizeof rate, " in %.3g s (%s, %.0f poses/s)\n", sweep.seconds,
                counted(sweep.threads, "thread").c_str(),
                sweep.seconds > 0 ? static_cast<double>(poses) / sweep.seconds : 0.0);
  out << rate;
  if (!sweep.fixed_parameters.empty()) out << "  at " << parameters_text(sweep.fixed_parameters) << '\n';
  for (const auto& warning : sweep.warnings) out << "  warning: " << warning << '\n';
  out << "  status:";
  std::size_t large = 0;
  for (const auto& r : sweep.results) large += r.large_deflection ? 1 : 0;
  for (auto status : {PoseStatus::ok, PoseStatus::singular, PoseStatus::free_motion, PoseStatus::invalid}) {
    std::size_t n = 0;
    for (const auto& r : sweep.results) n += r.status == status ? 1 : 0;
    if (n > 0) out << ' ' << to_string(status) << ' ' << n;
    if (status == PoseStatus::ok && large > 0) out << " (" << large << " with large deflections)";
  }
  out << '\n';
  for (std::size_t pose = 0; pose < poses; ++pose) {
    if (!sweep.results[pose].large_deflection) continue;
    out << "  first pose with large deflections (" << pose_text(sweep, pose) << "): " << sweep.results[pose].message
        << '\n';
    break;
  }
  for (std::size_t pose = 0; pose < poses; ++pose) {
    if (sweep.results[pose].status == PoseStatus::ok) continue;
    out << "  first failed pose (" << pose_text(sweep, pose) << "): " << to_string(sweep.results[pose].status)
        << ": " << sweep.results[pose].message << '\n';
    break;
  }
  for (const auto& column : sweep_columns(sweep, false)) {
    const auto worst = worst_pose(sweep, column);
    if (!worst) continue;
    out << "  " << (column.worst_is_largest ? "largest  " : "smallest ") << column.name << " = "
        << with_unit(column_value(sweep, column, *worst), column.unit) << " at " << pose_text(sweep, *worst) << '\n';
  }
  out << "wrote";
  for (const auto& f : files) out << ' ' << f.string();
  out << '\n';
}

// What --plot needs of the grid, checked before any pose is solved.
void check_plot_grid(const std::vector<GridAxis>& axes, bool from_pose_file) {
  if (from_pose_file || axes.empty() || axes.size() > 2)
    throw UsageError("--plot draws a line over a 1-D grid or a map over a 2-D grid; this sweep has " +
                     (from_pose_file ? std::string("a list of poses") : std::to_string(axes.size()) + " grid axes"));
  for (const auto& axis : axes) {
    const bool ascending = axis.start < axis.stop || (axes.size() == 1 && axis.count == 1);
    if (!ascending || (axes.size() == 2 && axis.count < 2))
      throw UsageError("--plot: the grid of '" + axis.parameter + "' must run upwards (START < STOP)" +
                       (axes.size() == 2 ? " with at least 2 values" : "") + " for a plot");
  }
}

// Output files must not be inputs or each other, and their folder must exist: checked before
// the sweep, so that a long sweep does not end in an error that writes nothing.
void check_files(const SweepCommand& command, const fs::path& csv, const fs::path& summary) {
  std::vector<std::pair<fs::path, std::string>> inputs{{command.model_file, "the model file"}};
  if (!command.poses_file.empty()) inputs.emplace_back(command.poses_file, "the pose file");
  for (const auto& [output, option] : {std::pair{csv, "--csv"}, std::pair{summary, "the summary (--summary)"}}) {
    for (const auto& [input, what] : inputs)
      if (same_file(output, input))
        throw UsageError(std::string(option) + " '" + output.string() + "' is " + what + "; choose another name");
    const fs::path folder = output.parent_path().empty() ? fs::path(".") : output.parent_path();
    std::error_code error;
    if (!fs::is_directory(folder, error))
      throw UsageError(std::string(option) + " '" + output.string() + "': the folder '" + folder.string() +
                       "' does not exist");
  }
  if (same_file(csv, summary))
    throw UsageError("the summary '" + summary.string() + "' would replace the CSV; choose another name for --summary");
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
  if (direction.isZero(0)) throw UsageError("--direction '" + text + "': the direction must not be zero");
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
    if (!value) throw UsageError("--set '" + setting + "': write NAME=VALUE with a finite number, e.g. x=0.1");
    if (!parsed.emplace(setting.substr(0, equals), *value).second)
      throw UsageError("--set '" + setting + "': the parameter is set twice");
  }
  return parsed;
}

int run_sweep(const SweepCommand& command) {
  if (command.grids.empty() == command.poses_file.empty())
    throw UsageError("give the poses either as --grid NAME=START:STOP:COUNT (one per swept parameter) or as --poses FILE.csv");
  std::vector<GridAxis> axes;
  for (const auto& spec : command.grids) axes.push_back(parse_grid(spec));
  if (command.plot) check_plot_grid(axes, !command.poses_file.empty());
  const fs::path csv(command.csv_file);
  const fs::path summary = command.summary_file.empty()
                               ? csv.parent_path() / (csv.stem().string() + ".summary.json")
                               : fs::path(command.summary_file);
  check_files(command, csv, summary);
  const fs::path view = csv.parent_path() / (csv.stem().string() + ".html");
  if (command.view && (same_file(view, command.model_file) || same_file(view, csv)))
    throw UsageError("--view would write '" + view.string() + "' over an input or the CSV; name the CSV otherwise");

  const ModelFamily family = load_model_family(command.model_file, command.limits, parse_settings(command.settings));
  const PoseTable poses = command.poses_file.empty() ? grid_poses(std::move(axes)) : read_pose_table(command.poses_file);

  SweepOptions options;
  options.solve = command.solve;
  options.keep_matrices = command.full;
  const Model at_defaults = family.build(family.default_values());
  if (command.plot) {
    // The columns to plot exist, and a matrix entry is kept for its plot even without --full.
    SweepResult columns_of;
    if (command.solve.direction) columns_of.direction = command.solve.direction;
    for (const auto& e : at_defaults.end_effectors) columns_of.end_effectors.push_back(e.name);
    for (const auto& column : plotted_columns(columns_of, command))
      if (column.quantity == SweepQuantity::compliance || column.quantity == SweepQuantity::stiffness)
        options.keep_matrices = true;
  }

  ProgressBar bar(!command.quiet);
  options.threads = command.threads;
  options.progress = [&bar](std::size_t done, std::size_t total) { bar.update(done, total); };
  const SweepResult result = sweep(family, poses, options);
  bar.finish();

  std::vector<fs::path> files{csv, summary};
  write_sweep_csv(result, command.full, csv);
  write_sweep_summary(result, command.full, csv.filename().string(), summary);
  if (command.plot) {
    const auto plots = write_plots(result, command, at_defaults);
    files.insert(files.end(), plots.begin(), plots.end());
  }
  if (command.view) {
    write_sweep_view(result, view);
    files.push_back(view);
  }
  print_sweep_summary(std::cout, result, files);
  return exit_success;
}

}  // namespace stiffmsa::cli
