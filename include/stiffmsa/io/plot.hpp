#pragma once
// Pictures of a sweep: a heatmap over a 2-D grid of parameter values and a line plot over a 1-D
// one, as PNG or SVG (chosen by the file's extension). The plots know nothing of models: they
// draw numbers with their names and units. Files are written whole or not at all.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace stiffmsa {

struct PlotAxis {
  std::string name;            // e.g. a parameter's name, "x"
  std::string unit;            // e.g. "m"; empty: no unit shown
  std::vector<double> values;  // the grid coordinates, ascending
};

// How values map to colours (heatmap) or heights (line plot). Stiffness near a singular pose
// spans decades, where a logarithmic scale shows the map and a linear one shows one spot.
enum class PlotScale { linear, logarithmic };

struct Heatmap {
  std::string title;
  PlotAxis x, y;
  std::string quantity;  // the colour bar's label, e.g. "platform.k_trans_min"
  std::string unit;      // e.g. "N/m"
  // values[iy * x.values.size() + ix]; NaN where the pose has no value (a failed pose), drawn
  // in a colour outside the colour bar and named in the legend.
  std::vector<double> values;
  PlotScale scale = PlotScale::linear;
  // A pose to mark with a symbol and a label (the worst pose): {ix, iy}.
  std::optional<std::pair<std::size_t, std::size_t>> marked;
  std::string marked_label;  // e.g. "softest: 1.24e+05 N/m"
  // What a NaN cell means, for the legend.
  std::string no_value_label = "no value (failed pose)";
  // A second, smaller line under the title: what the map holds fixed (empty: none).
  std::string subtitle;
  // Cells to mark with a ring, by value index (empty: none), and what the ring means.
  std::vector<bool> flagged;
  std::string flagged_label;
};

struct LinePlot {
  std::string title;
  PlotAxis x;
  std::string quantity;
  std::string unit;
  std::vector<double> values;  // one per x value; NaN: a gap in the line
  PlotScale scale = PlotScale::linear;
  std::optional<std::size_t> marked;
  std::string marked_label;
  std::string no_value_label = "no value (failed pose)";
  std::string subtitle;
  std::vector<bool> flagged;  // points to mark with a ring, one per value (empty: none)
  std::string flagged_label;
};

// Writes the picture to `file`: `.png` or `.svg`. Throws UsageError for another extension or
// data whose sizes do not match, IoError when the file cannot be written.
void write_plot(const Heatmap& plot, const std::filesystem::path& file);
void write_plot(const LinePlot& plot, const std::filesystem::path& file);

}  // namespace stiffmsa
