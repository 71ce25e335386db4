#include "sweep_output.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "stiffmsa/io/atomic_file.hpp"
#include "summary.hpp"
#if STIFFMSA_CLI_HDF5
#include "stiffmsa/io/sweep_hdf5.hpp"
#endif

namespace stiffmsa::cli {

namespace {

namespace fs = std::filesystem;

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
    text += description.run.poses.parameters[k] + " = " +
            value_with_unit(values[k], description.run.units[k]);
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

// "(0, 0, -100)"
std::string vector_text(const Vec3& v) {
  return "(" + shortest_text(v(0)) + ", " + shortest_text(v(1)) + ", " + shortest_text(v(2)) + ")";
}

// Plots of one column over the grid, PNG and SVG: map.csv -> map.E.k_trans_min.png. Their
// subtitles name the parameters held fixed and, on deflection maps, the loads; poses flagged
// (large deflections) are ringed.
std::vector<fs::path> write_plots(const SweepDescription& description, const SweepColumn& column,
                                  std::vector<double> values, const std::vector<bool>& flagged,
                                  const fs::path& base) {
  const auto& grid = description.run.poses.grid;
  const auto worst = worst_of(column, values);
  const std::string label = worst ? std::string(column.worst_is_largest ? "largest" : "smallest") +
                                        ": " + with_unit(values[*worst], column.unit)
                                  : std::string();
  bool any_failed = false, any_rigid = false;
  for (double& value : values) {
    any_failed = any_failed || std::isnan(value);
    if (std::isinf(value)) {
      value = NAN;  // a rigidly held direction has no colour on the scale
      any_rigid = true;
    }
  }
  const std::string no_value = any_rigid
                                   ? (any_failed ? "no value: failed pose, or rigid (infinite)"
                                                 : "rigid direction (infinite stiffness)")
                                   : "no value (failed pose)";
  const std::string title = description.run.model + ": " + column.name;
  const bool deflection = column.quantity == SweepQuantity::deflection_trans ||
                          column.quantity == SweepQuantity::deflection_rot;
  const auto& fixed = description.run.fixed_parameters;
  std::string subtitle = fixed.empty() ? "" : "at " + parameters_text(fixed);
  if (deflection) subtitle += (subtitle.empty() ? "under " : "; under ") + description.loads;
  const std::string flagged_label =
      "deflections beyond the linear method's range (large_deflection)";
  const auto axis = [&](std::size_t k) {
    PlotAxis a{grid[k].parameter, description.run.units[k], {}};
    for (std::size_t i = 0; i < grid[k].count; ++i) a.values.push_back(grid[k].value(i));
    return a;
  };
  std::vector<fs::path> written;
  for (const char* extension : {".png", ".svg"}) {
    const fs::path file = base.string() + "." + column.name + extension;
    if (grid.size() == 1) {
      LinePlot plot{title, axis(0), column.name, column.unit, values,  scale_for(values),
                    worst, label,   no_value,    subtitle,    flagged, flagged_label};
      write_plot(plot, file);
    } else {
      Heatmap plot{title,    axis(0),           axis(1),      column.name, column.unit,
                   values,   scale_for(values), std::nullopt, label,       no_value,
                   subtitle, flagged,           flagged_label};
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
  std::vector<bool> flagged;                 // per pose when plotting: large deflections
  bool any_flagged = false;

  State(const SweepDescription& d, SweepFiles f, std::size_t first)
      : description(d),
        files(std::move(f)),
        first_pose(first),
        next_pose(first),
        summary(d.columns) {}
};

SweepOutput::SweepOutput(const SweepDescription& description, SweepFiles files,
                         std::size_t first_pose, std::size_t poses)
    : state_(std::make_unique<State>(description, std::move(files), first_pose)) {
  State& s = *state_;
  // A plot holds one number per pose of each plotted column; more than its pixels show anyway.
  if (!s.files.plotted.empty() && poses > kMaxPosesInMemory)
    throw UsageError("--plot: the grid has " + std::to_string(poses) +
                     " poses; plots are drawn of at most " + std::to_string(kMaxPosesInMemory));
  for (std::size_t p = 0; p < s.files.plotted.size(); ++p) s.plotted.emplace_back(poses, NAN);
  if (!s.files.plotted.empty()) s.flagged.assign(poses, false);
  if (!s.files.csv.empty()) {
    s.csv.emplace(s.files.csv);
    s.csv->append(sweep_csv_header(description.run.poses.parameters, description.columns));
  }
  if (!s.files.hdf5.empty()) {
#if STIFFMSA_CLI_HDF5
    s.hdf5.emplace(s.files.hdf5, description.run.poses.parameters, description.run.units,
                   description.columns);
#else
    throw UsageError("this build of stiffmsa writes no HDF5 (built without HDF5); write --csv");
#endif
  }
}

SweepOutput::~SweepOutput() = default;

BlockShape SweepOutput::shape() const {
  return {&state_->description, state_->files.plotted, state_->csv.has_value(),
          !state_->files.hdf5.empty()};
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
      s.plotted[p][block.rows.first_pose - s.first_pose + row] =
          block.plotted[row * s.plotted.size() + p];
  if (!s.flagged.empty())
    for (std::size_t row = 0; row < block.rows.size(); ++row)
      if (block.rows.large_deflections[row] != 0) {
        s.flagged[block.rows.first_pose - s.first_pose + row] = true;
        s.any_flagged = true;
      }
}

std::vector<fs::path> SweepOutput::finish(std::size_t threads, double seconds,
                                          const std::string& extra_json) {
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
  if (!s.any_flagged) s.flagged.clear();  // no rings and no legend entry for them
  for (std::size_t p = 0; p < s.plotted.size(); ++p) {
    const auto plots = write_plots(s.description, s.files.plotted[p], std::move(s.plotted[p]),
                                   s.flagged, s.files.plot_base);
    written.insert(written.end(), plots.begin(), plots.end());
  }
  return written;
}

namespace {

SweepBlock finish_block(const BlockShape& shape, SweepRows rows, std::vector<double> plotted,
                        std::size_t threads, double seconds) {
  SweepBlock block{
      std::move(rows), SweepSummary(shape.description->columns), {}, std::move(plotted), threads,
      seconds};
  block.summary.add(block.rows);
  if (shape.csv) append_sweep_csv_rows(block.csv, block.rows);
  if (!shape.rows) {
    // Only the count of rows and their large-deflection flags (for plots) travel on: the CSV
    // lines and the summary say the rest.
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
  return finish_block(shape, sweep_rows(solved, shape.description->columns, first_pose),
                      std::move(plotted), solved.threads, solved.seconds);
}

SweepBlock make_block(const BlockShape& shape, SweepRows rows) {
  const auto& columns = shape.description->columns;
  std::vector<std::size_t> index;
  for (const auto& column : shape.plotted) {
    std::size_t k = 0;
    while (k < columns.size() && columns[k].name != column.name) ++k;
    if (k == columns.size())
      throw UsageError("--plot-column '" + column.name +
                       "': the rows have no such column (written without --full?)");
    index.push_back(k);
  }
  std::vector<double> plotted;
  plotted.reserve(rows.size() * index.size());
  for (std::size_t row = 0; row < rows.size(); ++row)
    for (std::size_t k : index) plotted.push_back(rows.value(row, k));
  return finish_block(shape, std::move(rows), std::move(plotted), 1, 0);
}

void print_sweep_summary(std::ostream& out, const SweepDescription& description,
                         const SweepSummary& summary, std::size_t threads, double seconds,
                         const std::vector<fs::path>& files, std::size_t ranks) {
  const std::size_t poses = summary.poses();
  out << "sweep of " << description.run.model << ": " << poses << " poses over "
      << name_list(description.run.poses.parameters);
  const std::string workers = ranks > 1
                                  ? counted(ranks, "rank") + " of " + counted(threads, "thread")
                                  : counted(threads, "thread");
  char rate[160];
  std::snprintf(rate, sizeof rate, " in %.3g s (%s, %.0f poses/s)\n", seconds, workers.c_str(),
                seconds > 0 ? static_cast<double>(poses) / seconds : 0.0);
  out << rate;
  const auto& fixed = description.run.fixed_parameters;
  if (!fixed.empty()) out << "  at " << parameters_text(fixed) << '\n';
  for (const auto& warning : description.run.warnings) out << "  warning: " << warning << '\n';
  out << "  status:";
  for (auto status : kPoseStatuses) {
    if (summary.count(status) > 0) out << ' ' << to_string(status) << ' ' << summary.count(status);
    if (status == PoseStatus::ok && summary.large_deflections() > 0)
      out << " (" << summary.large_deflections() << " with large deflections)";
  }
  out << '\n';
  if (const auto& large = summary.first_large_deflection())
    out << "  first pose with large deflections (" << pose_text(description, large->parameters)
        << "): " << large->message << '\n';
  if (const auto& failed = summary.first_failed())
    out << "  first failed pose (" << pose_text(description, failed->parameters)
        << "): " << to_string(failed->status) << ": " << failed->message << '\n';
  for (std::size_t c = 0; c < summary.columns().size(); ++c) {
    const SweepColumn& column = summary.columns()[c];
    const auto& worst = summary.worst(c);
    if (!worst || column.quantity == SweepQuantity::compliance ||
        column.quantity == SweepQuantity::stiffness)
      continue;
    out << "  " << (column.worst_is_largest ? "largest  " : "smallest ") << column.name << " = "
        << with_unit(worst->value, column.unit) << " at "
        << pose_text(description, worst->parameters) << '\n';
  }
  out << "wrote";
  for (const auto& f : files) out << ' ' << f.string();
  out << '\n';
}

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
  if (model.loads.size() > shown)
    text += "; and " + counted(model.loads.size() - shown, "more load");
  return text.empty() ? "no loads" : text;
}

std::vector<SweepColumn> plotted_columns(const SweepResult& description,
                                         const std::vector<std::string>& names) {
  std::vector<SweepColumn> columns;
  if (names.empty()) {
    for (const auto& column : sweep_columns(description, false))
      if (column.quantity == SweepQuantity::k_trans_min ||
          column.quantity == SweepQuantity::deflection_trans)
        columns.push_back(column);
    return columns;
  }
  for (const auto& name : names) {
    auto column = find_sweep_column(description, name);
    if (!column) {
      std::vector<std::string> known;
      for (const auto& c : sweep_columns(description, false)) known.push_back(c.name);
      throw UsageError("--plot-column '" + name + "': no such column; columns are " +
                       name_list(known) +
                       " and the compliance and stiffness entries E.C11 … E.K66");
    }
    columns.push_back(*column);
  }
  return columns;
}

void check_plot_grid(const std::vector<GridAxis>& axes, bool from_pose_file) {
  if (from_pose_file || axes.empty() || axes.size() > 2)
    throw UsageError(
        "--plot draws a line over a 1-D grid or a map over a 2-D grid; this sweep has " +
        (from_pose_file ? std::string("a list of poses")
                        : std::to_string(axes.size()) + " grid axes"));
  for (const auto& axis : axes) {
    const bool ascending = axis.start < axis.stop || (axes.size() == 1 && axis.count == 1);
    if (!ascending || (axes.size() == 2 && axis.count < 2))
      throw UsageError("--plot: the grid of '" + axis.parameter +
                       "' must run upwards (START < STOP)" +
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
  std::fprintf(stderr, "\rsweep [%s] %3d%% %zu/%zu poses", bar.c_str(),
               static_cast<int>(fraction * 100), done, total);
  if (done > 0 && done < total)
    std::fprintf(stderr, ", %.0f s left   ",
                 elapsed * static_cast<double>(total - done) / static_cast<double>(done));
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
