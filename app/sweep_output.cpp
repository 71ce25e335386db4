#include "sweep_output.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "stiffmsa/io/atomic_file.hpp"
#if STIFFMSA_CLI_HDF5
#include "stiffmsa/io/sweep_hdf5.hpp"
#endif

namespace stiffmsa::cli {

namespace {

namespace fs = std::filesystem;

std::string comma_separated(const std::vector<std::string>& names) {
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i) text += (i > 0 ? ", " : "") + names[i];
  return text;
}

std::string with_unit(double value, const std::string& unit) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.4g", value);
  return unit.empty() ? std::string(buffer) : std::string(buffer) + " " + unit;
}

// "x = 0.1 m, y = 0.2 m"
std::string pose_text(const SweepDescription& description, const std::vector<double>& values) {
  std::string text;
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (k > 0) text += ", ";
    text += description.run.poses.parameters[k] + " = " + with_unit(values[k], description.run.units[k]);
  }
  return text;
}

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

// The worst pose of a plotted column among its values (pose order), as worst_pose finds it.
std::optional<std::size_t> worst_of(const SweepColumn& column, const std::vector<double>& values) {
  std::optional<std::size_t> worst;
  for (std::size_t pose = 0; pose < values.size(); ++pose)
    if (is_worse(column, values[pose], worst ? values[*worst] : NAN)) worst = pose;
  return worst;
}

// Plots of one column over the grid, PNG and SVG: map.csv -> map.E.k_trans_min.png
std::vector<fs::path> write_plots(const SweepDescription& description, const SweepColumn& column,
                                  std::vector<double> values, const fs::path& base) {
  const auto& grid = description.run.poses.grid;
  const auto worst = worst_of(column, values);
  const std::string label = worst ? std::string(column.worst_is_largest ? "largest" : "smallest") + ": " +
                                        with_unit(values[*worst], column.unit)
                                  : std::string();
  bool any_failed = false, any_rigid = false;
  for (double& value : values) {
    any_failed = any_failed || std::isnan(value);
    if (std::isinf(value)) {
      value = NAN;  // a rigidly held direction has no colour on the scale
      any_rigid = true;
    }
  }
  const std::string no_value = any_rigid ? (any_failed ? "no value: failed pose, or rigid (infinite)"
                                                       : "rigid direction (infinite stiffness)")
                                         : "no value (failed pose)";
  const std::string title = description.run.model + ": " + column.name;
  const auto axis = [&](std::size_t k) {
    PlotAxis a{grid[k].parameter, description.run.units[k], {}};
    for (std::size_t i = 0; i < grid[k].count; ++i) a.values.push_back(grid[k].value(i));
    return a;
  };
  std::vector<fs::path> written;
  for (const char* extension : {".png", ".svg"}) {
    const fs::path file = base.string() + "." + column.name + extension;
    if (grid.size() == 1) {
      LinePlot plot{title, axis(0), column.name, column.unit, values, scale_for(values), worst, label, no_value};
      write_plot(plot, file);
    } else {
      Heatmap plot{title, axis(0), axis(1), column.name, column.unit, values, scale_for(values), std::nullopt, label,
                   no_value};
      if (worst) plot.marked = std::pair{*worst % grid[0].count, *worst / grid[0].count};
      write_plot(plot, file);
    }
    written.push_back(file);
  }
  return written;
}

}  // namespace

struct SweepOutput::State {
  SweepDescription description;
  SweepFiles files;
  std::size_t first_pose;
  std::size_t next_pose;
  SweepSummary summary;
  std::optional<AtomicFileWriter> csv;
#if STIFFMSA_CLI_HDF5
  std::optional<SweepHdf5Writer> hdf5;
#endif
  std::vector<std::vector<double>> plotted;  // per plotted column, per pose

  State(const SweepDescription& d, SweepFiles f, std::size_t first)
      : description(d), files(std::move(f)), first_pose(first), next_pose(first), summary(d.columns) {}
};

SweepOutput::SweepOutput(const SweepDescription& description, SweepFiles files, std::size_t first_pose,
                         std::size_t poses)
    : state_(std::make_unique<State>(description, std::move(files), first_pose)) {
  State& s = *state_;
  // A plot holds one number per pose of each plotted column; more than its pixels show anyway.
  constexpr std::size_t max_plotted_poses = 10'000'000;
  if (!s.files.plotted.empty() && poses > max_plotted_poses)
    throw UsageError("--plot: the grid has " + std::to_string(poses) + " poses; plots are drawn of at most " +
                     std::to_string(max_plotted_poses));
  for (std::size_t p = 0; p < s.files.plotted.size(); ++p) s.plotted.emplace_back(poses, NAN);
  if (!s.files.csv.empty()) {
    s.csv.emplace(s.files.csv);
    s.csv->append(sweep_csv_header(description.run.poses.parameters, description.columns));
  }
  if (!s.files.hdf5.empty()) {
#if STIFFMSA_CLI_HDF5
    s.hdf5.emplace(s.files.hdf5, description.run.poses.parameters, description.run.units, description.columns);
#else
    throw UsageError("this build of stiffmsa writes no HDF5 (built without HDF5); write --csv");
#endif
  }
}

SweepOutput::~SweepOutput() = default;

BlockShape SweepOutput::shape() const {
  return {&state_->description, state_->files.plotted, state_->csv.has_value(), !state_->files.hdf5.empty()};
}

std::vector<fs::path> SweepOutput::temporary_files() const {
  std::vector<fs::path> files;
  if (state_->csv) files.push_back(state_->csv->temporary_path());
#if STIFFMSA_CLI_HDF5
  if (state_->hdf5) files.push_back(state_->hdf5->temporary_path());
#endif
  return files;
}

const SweepSummary& SweepOutput::summary() const { return state_->summary; }

void SweepOutput::write(const SweepBlock& block) {
  State& s = *state_;
  if (block.rows.first_pose != s.next_pose || block.rows.size() != block.summary.poses() ||
      block.plotted.size() != block.rows.size() * s.plotted.size())
    throw Error("internal error: sweep rows arrived out of order");
  s.summary.add(block.summary);
  s.next_pose += block.rows.size();
  if (s.csv) s.csv->append(block.csv);
#if STIFFMSA_CLI_HDF5
  if (s.hdf5) s.hdf5->append(block.rows);
#endif
  for (std::size_t p = 0; p < s.plotted.size(); ++p)
    for (std::size_t row = 0; row < block.rows.size(); ++row)
      s.plotted[p][block.rows.first_pose - s.first_pose + row] = block.plotted[row * s.plotted.size() + p];
}

std::vector<fs::path> SweepOutput::finish(std::size_t threads, double seconds, const std::string& extra_json) {
  State& s = *state_;
  SweepResult run = s.description.run;
  run.threads = threads;
  run.seconds = seconds;
  std::string summary_json = sweep_summary_to_json(run, s.description.full, s.summary,
                                                   s.files.csv.filename().string(), s.first_pose);
  auto extra = extra_json.empty() ? nlohmann::json::object() : nlohmann::json::parse(extra_json);
  if (!s.files.hdf5.empty()) extra["hdf5"] = s.files.hdf5.filename().string();
  if (!extra.empty()) {
    auto summary = nlohmann::json::parse(summary_json);
    summary.update(extra);
    summary_json = summary.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  }
  std::vector<fs::path> written;
  if (s.csv) {
    s.csv->commit();
    written.push_back(s.files.csv);
  }
#if STIFFMSA_CLI_HDF5
  if (s.hdf5) {
    s.hdf5->commit(summary_json, s.summary);
    written.push_back(s.files.hdf5);
  }
#endif
  write_file_atomically(s.files.summary, summary_json);
  written.push_back(s.files.summary);
  for (std::size_t p = 0; p < s.plotted.size(); ++p) {
    const auto plots = write_plots(s.description, s.files.plotted[p], std::move(s.plotted[p]), s.files.plot_base);
    written.insert(written.end(), plots.begin(), plots.end());
  }
  return written;
}

namespace {

SweepBlock finish_block(const BlockShape& shape, SweepRows rows, std::vector<double> plotted, std::size_t threads,
                        double seconds) {
  SweepBlock block{std::move(rows), SweepSummary(shape.description->columns), {}, std::move(plotted), threads,
                   seconds};
  block.summary.add(block.rows);
  if (shape.csv) append_sweep_csv_rows(block.csv, block.rows);
  if (!shape.rows) {
    // Only the count of rows travels on: the CSV lines and the summary say the rest.
    block.rows.parameters.clear();
    block.rows.messages.clear();
    block.rows.values.clear();
  }
  return block;
}

}  // namespace

SweepBlock make_block(const BlockShape& shape, const SweepResult& solved, std::size_t first_pose) {
  // A plotted matrix entry need not be a column of the rows (a plot without --full).
  std::vector<double> plotted;
  plotted.reserve(solved.results.size() * shape.plotted.size());
  for (std::size_t pose = 0; pose < solved.results.size(); ++pose)
    for (const auto& column : shape.plotted) plotted.push_back(column_value(solved, column, pose));
  return finish_block(shape, sweep_rows(solved, shape.description->columns, first_pose), std::move(plotted),
                      solved.threads, solved.seconds);
}

SweepBlock make_block(const BlockShape& shape, SweepRows rows) {
  const auto& columns = shape.description->columns;
  std::vector<std::size_t> index;
  for (const auto& column : shape.plotted) {
    std::size_t k = 0;
    while (k < columns.size() && columns[k].name != column.name) ++k;
    if (k == columns.size())
      throw UsageError("--plot-column '" + column.name + "': the rows have no such column (written without --full?)");
    index.push_back(k);
  }
  std::vector<double> plotted;
  plotted.reserve(rows.size() * index.size());
  for (std::size_t row = 0; row < rows.size(); ++row)
    for (std::size_t k : index) plotted.push_back(rows.value(row, k));
  return finish_block(shape, std::move(rows), std::move(plotted), 1, 0);
}

void print_sweep_summary(std::ostream& out, const SweepDescription& description, const SweepSummary& summary,
                         std::size_t threads, double seconds, const std::vector<fs::path>& files, std::size_t ranks) {
  const std::size_t poses = summary.poses();
  out << "sweep of " << description.run.model << ": " << poses << " poses over "
      << comma_separated(description.run.poses.parameters);
  char rate[128];
  if (ranks > 1)
    std::snprintf(rate, sizeof rate, " in %.3g s (%zu ranks of %zu threads, %.0f poses/s)\n", seconds, ranks, threads,
                  seconds > 0 ? static_cast<double>(poses) / seconds : 0.0);
  else
    std::snprintf(rate, sizeof rate, " in %.3g s (%zu threads, %.0f poses/s)\n", seconds, threads,
                  seconds > 0 ? static_cast<double>(poses) / seconds : 0.0);
  out << rate << "  status:";
  for (auto status : {PoseStatus::ok, PoseStatus::singular, PoseStatus::free_motion, PoseStatus::invalid})
    if (summary.count(status) > 0) out << ' ' << to_string(status) << ' ' << summary.count(status);
  out << '\n';
  if (const auto& failed = summary.first_failed())
    out << "  first failed pose (" << pose_text(description, failed->parameters) << "): " << to_string(failed->status)
        << ": " << failed->message << '\n';
  for (std::size_t c = 0; c < summary.columns().size(); ++c) {
    const SweepColumn& column = summary.columns()[c];
    const auto& worst = summary.worst(c);
    if (!worst || column.quantity == SweepQuantity::compliance || column.quantity == SweepQuantity::stiffness) continue;
    out << "  " << (column.worst_is_largest ? "largest  " : "smallest ") << column.name << " = "
        << with_unit(worst->value, column.unit) << " at " << pose_text(description, worst->parameters) << '\n';
  }
  out << "wrote";
  for (const auto& f : files) out << ' ' << f.string();
  out << '\n';
}

std::vector<SweepColumn> plotted_columns(const SweepResult& description, const std::vector<std::string>& names) {
  std::vector<SweepColumn> columns;
  if (names.empty()) {
    for (const auto& column : sweep_columns(description, false))
      if (column.quantity == SweepQuantity::k_trans_min || column.quantity == SweepQuantity::deflection_trans)
        columns.push_back(column);
    return columns;
  }
  for (const auto& name : names) {
    auto column = find_sweep_column(description, name);
    if (!column) {
      std::vector<std::string> known;
      for (const auto& c : sweep_columns(description, false)) known.push_back(c.name);
      throw UsageError("--plot-column '" + name + "': no such column; columns are " + comma_separated(known) +
                       " and the compliance and stiffness entries E.C11 … E.K66");
    }
    columns.push_back(*column);
  }
  return columns;
}

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

}  // namespace stiffmsa::cli

namespace stiffmsa::cli {

ProgressBar::ProgressBar(bool enabled) : enabled_(enabled && ::isatty(STDERR_FILENO) == 1) {}

void ProgressBar::update(std::size_t done, std::size_t total) {
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

void ProgressBar::finish() {
  if (drawn_) std::fprintf(stderr, "\r\033[K");
  drawn_ = false;
}

double ProgressBar::seconds_since_start() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

}  // namespace stiffmsa::cli
