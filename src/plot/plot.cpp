// Heatmaps and line plots drawn with cairo. One drawing routine serves both formats: it paints
// on whatever surface it is given, so the PNG and the SVG of a plot show the same picture.
#include "stiffmsa/io/plot.hpp"

#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "stiffmsa/errors.hpp"
#include "stiffmsa/io/result_file.hpp"
#include "stiffmsa/number_text.hpp"

namespace stiffmsa {
namespace {

namespace fs = std::filesystem;

// Pixels in the PNG; the SVG uses the same number of CSS pixels.
constexpr int image_width = 800;
constexpr int image_height = 600;

constexpr double edge = 14;  // empty border around everything
constexpr double tick_length = 5;
constexpr double tick_gap = 4;  // between a tick and its label
constexpr double title_size = 16;
constexpr double label_size = 14;
constexpr double tick_size = 12;
constexpr double tick_line = tick_size * 1.25;
constexpr double label_line = label_size * 1.25;
constexpr double bar_gap = 20;
constexpr double bar_width = 18;

struct Rgb {
  double r, g, b;
};

constexpr Rgb rgb8(int r, int g, int b) { return {r / 255.0, g / 255.0, b / 255.0}; }

// A viridis-like map: lightness rises steadily from blue-violet to yellow, so equal steps in
// value look like equal steps in colour, and the map survives greyscale printing and the
// common colour-vision deficiencies. Linear interpolation between close anchors keeps that.
constexpr std::array<Rgb, 11> colour_map = {
    rgb8(68, 1, 84),    rgb8(72, 36, 117),  rgb8(65, 68, 135),  rgb8(53, 95, 141),
    rgb8(42, 120, 142), rgb8(33, 145, 140), rgb8(34, 168, 132), rgb8(68, 191, 112),
    rgb8(122, 209, 81), rgb8(189, 223, 38), rgb8(253, 231, 37)};

// The map has no neutral greys, so a failed pose can never be read as a value.
constexpr Rgb no_value_colour = rgb8(191, 191, 191);
constexpr Rgb black = rgb8(0, 0, 0);
constexpr Rgb white = rgb8(255, 255, 255);
constexpr Rgb line_colour = rgb8(31, 95, 168);

Rgb colour_at(double fraction) {
  const double position = std::clamp(fraction, 0.0, 1.0) * (colour_map.size() - 1);
  const std::size_t below = std::min(static_cast<std::size_t>(position), colour_map.size() - 2);
  const double t = position - static_cast<double>(below);
  const Rgb& a = colour_map[below];
  const Rgb& b = colour_map[below + 1];
  return {a.r + t * (b.r - a.r), a.g + t * (b.g - a.g), a.b + t * (b.b - a.b)};
}

// ---- Values and ticks -----------------------------------------------------------------------

// Where a value sits on its axis or colour bar: the value itself, or its log10. Values that
// cannot be placed (NaN, infinite, not positive on a log scale) are treated as no value.
std::optional<double> scaled(double value, PlotScale scale) {
  if (!std::isfinite(value) || (scale == PlotScale::logarithmic && value <= 0)) return {};
  return scale == PlotScale::linear ? value : std::log10(value);
}

struct Range {
  double lo, hi;
  double fraction(double at) const { return (at - lo) / (hi - lo); }
};

// A constant (or empty) set of values is widened so that the axis still has a length and a
// constant map shows the middle colour rather than an arbitrary end of the bar.
Range widened_if_flat(double lo, double hi, PlotScale scale) {
  if (lo > hi) return {0, 1};
  if (hi - lo > 1e-9 * std::max({1.0, std::abs(lo), std::abs(hi)})) return {lo, hi};
  double pad = 0.25;  // decades
  if (scale == PlotScale::linear) pad = lo != 0 ? 0.05 * std::abs(lo) : 1.0;
  return {lo - pad, hi + pad};
}

// The span of the values that can be drawn, with `margin` of it added at each end.
Range value_range(const std::vector<double>& values, PlotScale scale, double margin = 0) {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -lo;
  for (double value : values) {
    if (const auto at = scaled(value, scale)) {
      lo = std::min(lo, *at);
      hi = std::max(hi, *at);
    }
  }
  const Range range = widened_if_flat(lo, hi, scale);
  const double pad = (range.hi - range.lo) * margin;
  return {range.lo - pad, range.hi + pad};
}

struct Tick {
  double at;  // on the scaled axis
  std::string label;
};

int decimal_exponent(double value) {
  return static_cast<int>(std::floor(std::log10(std::abs(value)) + 1e-9));
}

std::string fixed(double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", std::clamp(decimals, 0, 15), value);
  std::string result = text;
  // A value rounded to zero from below would otherwise print as "-0".
  if (result.find_first_not_of("-0.") == std::string::npos) return result.substr(result[0] == '-');
  // A typographic minus: as wide as a plus, and not mistaken for a hyphen.
  if (result[0] == '-') result.replace(0, 1, "\u2212");
  return result;
}

// "1.5×10⁶": stiffnesses run to millions, and six zeros are harder to count than an
// exponent. A mantissa of one is left out where powers stand alone (decades on a log scale).
std::string power_label(double value, double step, bool bare_powers) {
  if (value == 0) return "0";
  static const std::array<const char*, 10> digits = {"⁰", "¹", "²", "³", "⁴",
                                                     "⁵", "⁶", "⁷", "⁸", "⁹"};
  const int exponent = decimal_exponent(value);
  std::string mantissa =
      fixed(value / std::pow(10.0, exponent), std::max(0, exponent - decimal_exponent(step)));
  if (mantissa.find('.') != std::string::npos) {
    mantissa.erase(mantissa.find_last_not_of('0') + 1);
    if (mantissa.back() == '.') mantissa.pop_back();
  }
  std::string power = exponent < 0 ? "10⁻" : "10";
  for (char digit : std::to_string(std::abs(exponent))) power += digits[digit - '0'];
  return bare_powers && mantissa == "1" ? power : mantissa + "×" + power;
}

// Multiples of 1, 2 or 5 times a power of ten, about `count` of them over [lo, hi].
std::vector<Tick> linear_ticks(double lo, double hi, int count) {
  const double rough = (hi - lo) / std::max(count, 1);
  const double magnitude = std::pow(10.0, std::floor(std::log10(rough)));
  double step = 10 * magnitude;
  for (double multiple : {5.0, 2.0, 1.0}) {
    if (multiple * magnitude >= rough * (1 - 1e-9)) step = multiple * magnitude;
  }
  const double first = std::ceil(lo / step - 1e-9);
  const double last = std::floor(hi / step + 1e-9);
  const double largest = std::max(std::abs(first), std::abs(last)) * step;
  const bool powers = largest >= 1e5 || (largest > 0 && largest < 1e-3);
  std::vector<Tick> ticks;
  for (double i = first; i <= last; ++i) {
    const double value = i == 0 ? 0.0 : i * step;
    ticks.push_back(
        {value, powers ? power_label(value, step, false) : fixed(value, -decimal_exponent(step))});
  }
  return ticks;
}

// Powers of ten; with less than about two decades also their 2 and 5 multiples; with too
// few of those, 1-2-5 steps of the value itself, placed logarithmically.
std::vector<Tick> log_ticks(Range range, int count) {
  std::vector<std::pair<int, int>> marks;  // {multiple, exponent}
  const double decades = range.hi - range.lo;
  const int every = std::max(1, static_cast<int>(std::ceil(decades / std::max(count, 1))));
  for (int k = static_cast<int>(std::floor(range.lo)); k <= std::ceil(range.hi); ++k) {
    for (int multiple : {1, 2, 5}) {
      const double at = k + std::log10(multiple);
      const bool shown = decades < 2.2 || (multiple == 1 && (k % every + every) % every == 0);
      if (shown && at >= range.lo - 1e-9 && at <= range.hi + 1e-9) marks.push_back({multiple, k});
    }
  }
  std::vector<Tick> ticks;
  if (marks.size() < 3) {
    for (Tick& tick : linear_ticks(std::pow(10.0, range.lo), std::pow(10.0, range.hi), count)) {
      if (tick.at > 0) ticks.push_back({std::log10(tick.at), std::move(tick.label)});
    }
    return ticks;
  }
  // Plain numbers while they are short; powers of ten for all ticks of the axis otherwise.
  const bool plain = std::all_of(marks.begin(), marks.end(),
                                 [](const auto& m) { return m.second >= -3 && m.second <= 4; });
  for (const auto& [multiple, k] : marks) {
    const double value = multiple * std::pow(10.0, k);
    ticks.push_back({std::log10(multiple) + k,
                     plain ? fixed(value, -k) : power_label(value, std::pow(10.0, k), true)});
  }
  return ticks;
}

std::vector<Tick> ticks_for(Range range, PlotScale scale, int count) {
  return scale == PlotScale::linear ? linear_ticks(range.lo, range.hi, count)
                                    : log_ticks(range, count);
}

// ---- Drawing primitives -----------------------------------------------------------------------

void set_colour(cairo_t* cr, Rgb c) { cairo_set_source_rgb(cr, c.r, c.g, c.b); }

void set_font(cairo_t* cr, double size, bool bold = false) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
}

double text_width(cairo_t* cr, const std::string& text) {
  cairo_text_extents_t extents;
  cairo_text_extents(cr, text.c_str(), &extents);
  return extents.x_advance;
}

double widest(cairo_t* cr, const std::vector<Tick>& ticks) {
  double widest = 0;
  for (const Tick& tick : ticks) widest = std::max(widest, text_width(cr, tick.label));
  return widest;
}

// Long user-supplied names must still fit: shrink the font rather than clip the text.
void set_font_to_fit(cairo_t* cr, const std::string& text, double size, double room,
                     bool bold = false) {
  set_font(cr, size, bold);
  while (size > 8 && text_width(cr, text) > room) set_font(cr, size -= 0.5, bold);
}

// The height of digits and capitals: text is placed by it, not by its tallest glyph, so that
// labels sit centred on their ticks whatever letters they contain.
double cap_height(cairo_t* cr) {
  cairo_text_extents_t digit;
  cairo_text_extents(cr, "0", &digit);
  return -digit.y_bearing;
}

// `along`: 0 puts the text's start at (x, y), 0.5 its middle, 1 its end; `across`: 0 its
// baseline, 0.5 its middle, 1 its top (cap height).
void draw_text(cairo_t* cr, const std::string& text, double x, double y, double along,
               double across, double angle = 0) {
  cairo_save(cr);
  cairo_translate(cr, x, y);
  cairo_rotate(cr, angle);
  cairo_move_to(cr, -along * text_width(cr, text), across * cap_height(cr));
  cairo_show_text(cr, text.c_str());
  cairo_restore(cr);
}

void draw_line(cairo_t* cr, double x0, double y0, double x1, double y1) {
  cairo_move_to(cr, x0, y0);
  cairo_line_to(cr, x1, y1);
  cairo_stroke(cr);
}

// Half-pixel positions keep one-pixel lines crisp in the PNG.
double crisp(double pixel) { return std::floor(pixel) + 0.5; }

// ---- Axes, titles, legend, marker -----------------------------------------------------------

struct Frame {
  double left, top, right, bottom;
  double width() const { return right - left; }
  double height() const { return bottom - top; }
  double x(Range range, double at) const { return left + range.fraction(at) * width(); }
  double y(Range range, double at) const { return bottom - range.fraction(at) * height(); }
};

void draw_outline(cairo_t* cr, const Frame& frame) {
  cairo_set_line_width(cr, 1);
  set_colour(cr, black);
  cairo_rectangle(cr, crisp(frame.left), crisp(frame.top), crisp(frame.right) - crisp(frame.left),
                  crisp(frame.bottom) - crisp(frame.top));
  cairo_stroke(cr);
}

std::string titled(const std::string& name, const std::string& unit) {
  return unit.empty() ? name : name + " [" + unit + "]";
}

// From the frame's bottom: tick labels, the x-axis title, then the legend line if any.
constexpr double x_title_offset = tick_length + tick_gap + tick_line + 8;
constexpr double legend_offset = x_title_offset + label_line + 6;

// The frame's top and bottom; its sides follow from the tick labels (see `place_sides`).
constexpr double subtitle_line = tick_size * 1.25 + 4;

Frame frame_for(const std::string& title, const std::string& subtitle, bool legend) {
  const double top = (title.empty() ? edge + 8 : edge + title_size * 1.25 + 14) +
                     (subtitle.empty() ? 0 : subtitle_line);
  return {0, top, 0, image_height - edge - legend_offset + 6 - (legend ? 6 + tick_line : 0)};
}

// Labels closer than their own size (plus a gap) would touch: keep each tick only if it is far
// enough from the last one kept.
std::vector<Tick> thinned(std::vector<Tick> ticks, const std::function<double(double)>& pixel,
                          double room) {
  std::vector<Tick> kept;
  for (Tick& tick : ticks) {
    if (kept.empty() || std::abs(pixel(tick.at) - pixel(kept.back().at)) >= room) {
      kept.push_back(std::move(tick));
    }
  }
  return kept;
}

std::vector<Tick> vertical_ticks(Range range, PlotScale scale, const Frame& frame) {
  const int count = std::max(2, static_cast<int>(frame.height() / 55));
  return thinned(
      ticks_for(range, scale, count), [&](double at) { return frame.y(range, at); }, tick_size + 8);
}

// Left: the y-axis title and tick labels; right: `right_room`. Then as many x ticks as fit:
// fewer when their labels are wide.
std::vector<Tick> place_sides(cairo_t* cr, Frame& frame, const std::vector<Tick>& y_ticks,
                              double right_room, Range x_range) {
  set_font(cr, tick_size);
  frame.left = edge + label_line + 8 + widest(cr, y_ticks) + tick_gap + tick_length;
  frame.right = image_width - right_room;
  std::vector<Tick> ticks;
  for (int count = std::max(2, static_cast<int>(frame.width() / 80)); count >= 1; --count) {
    ticks = linear_ticks(x_range.lo, x_range.hi, count);
    const double room = widest(cr, ticks) + 16;
    if (room * static_cast<double>(ticks.size() - 1) <= frame.width()) break;
  }
  return thinned(
      ticks, [&](double at) { return frame.x(x_range, at); }, widest(cr, ticks) + 12);
}

// Ticks and labels on one side of a vertical axis: the plot's left or the colour bar's right.
void draw_vertical_ticks(cairo_t* cr, const Frame& frame, Range range,
                         const std::vector<Tick>& ticks, bool on_right) {
  cairo_set_line_width(cr, 1);
  set_colour(cr, black);
  set_font(cr, tick_size);
  const double side = on_right ? frame.right : frame.left;
  const double outward = on_right ? 1 : -1;
  for (const Tick& tick : ticks) {
    const double y = crisp(frame.y(range, tick.at));
    draw_line(cr, side, y, side + outward * tick_length, y);
    draw_text(cr, tick.label, side + outward * (tick_length + tick_gap), y, on_right ? 0 : 1, 0.5);
  }
}

// A title reading upwards, its top facing left, centred along the frame's height.
void draw_vertical_title(cairo_t* cr, const Frame& frame, const std::string& title, double left) {
  set_colour(cr, black);
  set_font_to_fit(cr, title, label_size, frame.height() + 40);
  draw_text(cr, title, left, (frame.top + frame.bottom) / 2, 0.5, 1, -std::numbers::pi / 2);
}

// The frame, both axes with their ticks and titles, and the plot's title.
void draw_axes(cairo_t* cr, const Frame& frame, Range x_range, const std::vector<Tick>& x_ticks,
               Range y_range, const std::vector<Tick>& y_ticks, const std::string& x_title,
               const std::string& y_title, const std::string& title, const std::string& subtitle) {
  draw_outline(cr, frame);
  draw_vertical_ticks(cr, frame, y_range, y_ticks, false);
  draw_vertical_title(cr, frame, y_title, edge);
  for (const Tick& tick : x_ticks) {
    const double x = crisp(frame.x(x_range, tick.at));
    draw_line(cr, x, frame.bottom, x, frame.bottom + tick_length);
    draw_text(cr, tick.label, x, frame.bottom + tick_length + tick_gap, 0.5, 1);
  }
  set_font_to_fit(cr, x_title, label_size, image_width - 2 * edge);
  draw_text(cr, x_title, (frame.left + frame.right) / 2, frame.bottom + x_title_offset, 0.5, 1);
  if (title.empty()) return;
  set_font_to_fit(cr, title, title_size, image_width - 2 * edge, true);
  // Centred over the plot, unless that would push a long title off the image.
  const double half = text_width(cr, title) / 2;
  draw_text(cr, title,
            std::clamp((frame.left + frame.right) / 2, edge + half, image_width - edge - half),
            edge + 2, 0.5, 1);
  if (subtitle.empty()) return;
  set_font_to_fit(cr, subtitle, tick_size, image_width - 2 * edge);
  const double sub_half = text_width(cr, subtitle) / 2;
  draw_text(
      cr, subtitle,
      std::clamp((frame.left + frame.right) / 2, edge + sub_half, image_width - edge - sub_half),
      edge + 2 + title_size * 1.25 + 4, 0.5, 1);
}

// A black ring with a white outline around a flagged pose: it leaves the cell's colour or the
// point visible inside it.
void draw_ring(cairo_t* cr, double x, double y, double radius) {
  for (const auto& [colour, width] : {std::pair{white, 3.5}, std::pair{black, 1.5}}) {
    cairo_new_sub_path(cr);
    cairo_arc(cr, x, y, radius, 0, 2 * std::numbers::pi);
    cairo_set_line_width(cr, width);
    set_colour(cr, colour);
    cairo_stroke(cr);
  }
}

// The line under the x-axis title: a key to what is not on the colour bar or the line; then,
// where poses are flagged, the ring and what it means.
void draw_legend(cairo_t* cr, const Frame& frame, bool swatch, const std::string& text,
                 const std::string& ring_text) {
  const double top = frame.bottom + legend_offset;
  double x = frame.left;
  if (!text.empty() && swatch) {
    cairo_rectangle(cr, x + 0.5, top + 0.5, 16, 11);
    set_colour(cr, no_value_colour);
    cairo_fill_preserve(cr);
    set_colour(cr, rgb8(110, 110, 110));
    cairo_set_line_width(cr, 1);
    cairo_stroke(cr);
    x += 24;
  }
  set_colour(cr, black);
  set_font(cr, tick_size);
  if (!text.empty()) {
    draw_text(cr, text, x, top + 6, 0, 0.5);
    x += text_width(cr, text) + 24;
  }
  if (ring_text.empty()) return;
  draw_ring(cr, x + 6, top + 6, 5);
  set_colour(cr, black);
  set_font(cr, tick_size);
  draw_text(cr, ring_text, x + 16, top + 6, 0, 0.5);
}

// Whether the flags mark any pose.
bool any_flagged(const std::vector<bool>& flagged) {
  return std::find(flagged.begin(), flagged.end(), true) != flagged.end();
}

// A black cross with a white outline, visible on every colour of the map and on white; its
// label beside it, on whichever side keeps it inside the plot, on a light box so that it reads
// over any colour and over the line.
void draw_marker(cairo_t* cr, const Frame& frame, double x, double y, const std::string& label) {
  constexpr double arm = 7;
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  for (const auto& [colour, width] : {std::pair{white, 5.5}, std::pair{black, 2.5}}) {
    cairo_move_to(cr, x - arm, y - arm);
    cairo_line_to(cr, x + arm, y + arm);
    cairo_move_to(cr, x - arm, y + arm);
    cairo_line_to(cr, x + arm, y - arm);
    cairo_set_line_width(cr, width);
    set_colour(cr, colour);
    cairo_stroke(cr);
  }
  if (label.empty()) return;
  constexpr double padding = 4;
  constexpr double offset = arm + 6;
  set_font_to_fit(cr, label, tick_size, frame.width() - 4 * padding);
  const double width = text_width(cr, label);
  const double half_height = cap_height(cr) / 2 + padding;
  double left = x + offset;
  if (left + width + padding > frame.right - 2) left = x - offset - width;
  const double leftmost = frame.left + padding + 2;
  left = std::clamp(left, leftmost, std::max(leftmost, frame.right - padding - 2 - width));
  const double middle = std::clamp(y, frame.top + half_height + 2, frame.bottom - half_height - 2);
  cairo_rectangle(cr, std::round(left - padding) + 0.5, std::round(middle - half_height) + 0.5,
                  std::round(width + 2 * padding), std::round(2 * half_height));
  cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
  cairo_fill_preserve(cr);
  set_colour(cr, rgb8(90, 90, 90));
  cairo_set_line_width(cr, 1);
  cairo_stroke(cr);
  set_colour(cr, black);
  draw_text(cr, label, left, middle, 0, 0.5);
}

// ---- The two kinds of plot ------------------------------------------------------------------

// Each cell reaches halfway to its neighbours; the outer ones as far out as in.
std::vector<double> cell_edges(const std::vector<double>& centres) {
  const std::size_t n = centres.size();
  std::vector<double> edges(n + 1);
  for (std::size_t i = 1; i < n; ++i) edges[i] = (centres[i - 1] + centres[i]) / 2;
  edges[0] = centres[0] - (centres[1] - centres[0]) / 2;
  edges[n] = centres[n - 1] + (centres[n - 1] - centres[n - 2]) / 2;
  return edges;
}

void draw_heatmap(cairo_t* cr, const Heatmap& plot) {
  const std::vector<double> x_edges = cell_edges(plot.x.values);
  const std::vector<double> y_edges = cell_edges(plot.y.values);
  const Range x_range{x_edges.front(), x_edges.back()};
  const Range y_range{y_edges.front(), y_edges.back()};
  const Range colours = value_range(plot.values, plot.scale);
  const bool any_missing = std::any_of(plot.values.begin(), plot.values.end(),
                                       [&](double v) { return !scaled(v, plot.scale); });

  // Heights first: they fix the vertical ticks, whose labels' widths then fix the sides.
  const bool flags = any_flagged(plot.flagged);
  Frame frame = frame_for(plot.title, plot.subtitle, any_missing || flags);
  const std::vector<Tick> y_ticks = vertical_ticks(y_range, PlotScale::linear, frame);
  const std::vector<Tick> bar_ticks = vertical_ticks(colours, plot.scale, frame);
  set_font(cr, tick_size);
  const double bar_labels = tick_length + tick_gap + widest(cr, bar_ticks) + 10;
  const std::vector<Tick> x_ticks = place_sides(
      cr, frame, y_ticks, edge + label_line + bar_labels + bar_width + bar_gap, x_range);

  // Cells without antialiasing, each reaching half a pixel under its right and upper
  // neighbours (drawn later): no hairline seams, in the PNG or in an SVG viewer.
  cairo_save(cr);
  cairo_rectangle(cr, frame.left, frame.top, frame.width(), frame.height());
  cairo_clip(cr);
  cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);
  const std::size_t nx = plot.x.values.size();
  for (std::size_t iy = 0; iy < plot.y.values.size(); ++iy) {
    for (std::size_t ix = 0; ix < nx; ++ix) {
      const auto at = scaled(plot.values[iy * nx + ix], plot.scale);
      set_colour(cr, at ? colour_at(colours.fraction(*at)) : no_value_colour);
      const double left = frame.x(x_range, x_edges[ix]);
      const double top = frame.y(y_range, y_edges[iy + 1]);
      cairo_rectangle(cr, left, top - 0.5, frame.x(x_range, x_edges[ix + 1]) - left + 0.5,
                      frame.y(y_range, y_edges[iy]) - top + 0.5);
      cairo_fill(cr);
    }
  }
  cairo_restore(cr);
  draw_axes(cr, frame, x_range, x_ticks, y_range, y_ticks, titled(plot.x.name, plot.x.unit),
            titled(plot.y.name, plot.y.unit), plot.title, plot.subtitle);

  // The bar's gradient has the map's anchors as stops: it interpolates exactly as the cells.
  const Frame bar{frame.right + bar_gap, frame.top, frame.right + bar_gap + bar_width,
                  frame.bottom};
  cairo_pattern_t* gradient = cairo_pattern_create_linear(0, bar.bottom, 0, bar.top);
  for (std::size_t i = 0; i < colour_map.size(); ++i) {
    const Rgb& c = colour_map[i];
    cairo_pattern_add_color_stop_rgb(gradient, static_cast<double>(i) / (colour_map.size() - 1),
                                     c.r, c.g, c.b);
  }
  cairo_rectangle(cr, bar.left, bar.top, bar.width(), bar.height());
  cairo_set_source(cr, gradient);
  cairo_fill(cr);
  cairo_pattern_destroy(gradient);
  draw_outline(cr, bar);
  draw_vertical_ticks(cr, bar, colours, bar_ticks, true);
  draw_vertical_title(cr, bar, titled(plot.quantity, plot.unit), bar.right + bar_labels);

  if (flags) {
    for (std::size_t iy = 0; iy < plot.y.values.size(); ++iy)
      for (std::size_t ix = 0; ix < nx; ++ix) {
        if (!plot.flagged[iy * nx + ix]) continue;
        const double width = frame.x(x_range, x_edges[ix + 1]) - frame.x(x_range, x_edges[ix]);
        const double height = frame.y(y_range, y_edges[iy]) - frame.y(y_range, y_edges[iy + 1]);
        draw_ring(cr, frame.x(x_range, plot.x.values[ix]), frame.y(y_range, plot.y.values[iy]),
                  std::clamp(0.3 * std::min(width, height), 2.5, 6.0));
      }
  }
  if (any_missing || flags)
    draw_legend(cr, frame, true, any_missing ? plot.no_value_label : "",
                flags ? plot.flagged_label : "");
  if (plot.marked) {
    const auto [ix, iy] = *plot.marked;
    draw_marker(cr, frame, frame.x(x_range, plot.x.values[ix]), frame.y(y_range, plot.y.values[iy]),
                plot.marked_label);
  }
}

void draw_line_plot(cairo_t* cr, const LinePlot& plot) {
  const std::vector<double>& xs = plot.x.values;
  // A single pose still gets an axis around it.
  const Range x_range = value_range(xs, PlotScale::linear, xs.size() == 1 ? 0 : 0.03);
  const Range y_range = value_range(plot.values, plot.scale, 0.05);
  std::vector<std::optional<double>> heights;
  for (double value : plot.values) heights.push_back(scaled(value, plot.scale));
  const bool marked_missing = plot.marked && !heights[*plot.marked];
  std::string legend;
  if (std::count(heights.begin(), heights.end(), std::nullopt) > 0) {
    legend = "gaps: " + plot.no_value_label;
  }
  if (marked_missing && !plot.marked_label.empty()) {
    legend += (legend.empty() ? "" : ";   ") + plot.marked_label + " (no value)";
  }

  const bool flags = any_flagged(plot.flagged);
  Frame frame = frame_for(plot.title, plot.subtitle, !legend.empty() || flags);
  const std::vector<Tick> y_ticks = vertical_ticks(y_range, plot.scale, frame);
  const std::vector<Tick> x_ticks = place_sides(cr, frame, y_ticks, edge + 26, x_range);

  // Light grid lines under the data: values are read off a line plot, not just compared.
  cairo_set_line_width(cr, 1);
  set_colour(cr, rgb8(230, 230, 230));
  for (const Tick& tick : x_ticks) {
    const double x = crisp(frame.x(x_range, tick.at));
    draw_line(cr, x, frame.top, x, frame.bottom);
  }
  for (const Tick& tick : y_ticks) {
    const double y = crisp(frame.y(y_range, tick.at));
    draw_line(cr, frame.left, y, frame.right, y);
  }

  cairo_save(cr);
  cairo_rectangle(cr, frame.left, frame.top, frame.width(), frame.height());
  cairo_clip(cr);
  set_colour(cr, line_colour);
  bool pen_down = false;  // lifted at every missing value, leaving a gap
  for (std::size_t i = 0; i < xs.size(); ++i) {
    if (heights[i]) {
      const double x = frame.x(x_range, xs[i]);
      const double y = frame.y(y_range, *heights[i]);
      pen_down ? cairo_line_to(cr, x, y) : cairo_move_to(cr, x, y);
    }
    pen_down = heights[i].has_value();
  }
  cairo_set_line_width(cr, 1.8);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_stroke(cr);
  // Dense points would merge into a thick line: smaller dots then.
  const double spacing = frame.width() / static_cast<double>(std::max<std::size_t>(xs.size(), 1));
  const double radius = std::clamp(spacing / 4, 1.5, 2.6);
  for (std::size_t i = 0; i < xs.size(); ++i) {
    if (!heights[i]) continue;
    cairo_new_sub_path(cr);
    cairo_arc(cr, frame.x(x_range, xs[i]), frame.y(y_range, *heights[i]), radius, 0,
              2 * std::numbers::pi);
  }
  cairo_fill(cr);
  cairo_restore(cr);

  draw_axes(cr, frame, x_range, x_ticks, y_range, y_ticks, titled(plot.x.name, plot.x.unit),
            titled(plot.quantity, plot.unit), plot.title, plot.subtitle);
  if (flags)
    for (std::size_t i = 0; i < xs.size(); ++i)
      if (plot.flagged[i] && heights[i])
        draw_ring(cr, frame.x(x_range, xs[i]), frame.y(y_range, *heights[i]), 5.5);
  if (!legend.empty() || flags)
    draw_legend(cr, frame, false, legend, flags ? plot.flagged_label : "");
  if (plot.marked && !marked_missing) {
    draw_marker(cr, frame, frame.x(x_range, xs[*plot.marked]),
                frame.y(y_range, *heights[*plot.marked]), plot.marked_label);
  }
}

// ---- Checks, rendering and writing ------------------------------------------------------------

enum class Format { png, svg };

std::string cannot_write(const fs::path& file) {
  return "cannot write the plot '" + file.string() + "': ";
}

Format format_of(const fs::path& file) {
  std::string extension = file.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".png") return Format::png;
  if (extension == ".svg") return Format::svg;
  throw UsageError(cannot_write(file) + "the file name must end in .png or .svg");
}

void check_axis(const PlotAxis& axis, const char* which, std::size_t at_least,
                const fs::path& file) {
  const std::string name = cannot_write(file) + which + " axis '" + axis.name + "'";
  if (axis.values.size() < at_least) {
    throw UsageError(name + " has " + std::to_string(axis.values.size()) +
                     " values; this plot needs at least " + std::to_string(at_least));
  }
  for (std::size_t i = 0; i < axis.values.size(); ++i) {
    if (!std::isfinite(axis.values[i])) throw UsageError(name + " has a value that is not finite");
    if (i > 0 && !(axis.values[i] > axis.values[i - 1])) {
      throw UsageError(name + ": values must be strictly ascending");
    }
  }
}

void check_sizes(std::size_t values, std::size_t points, bool marked_inside, const fs::path& file) {
  if (values != points) {
    throw UsageError(cannot_write(file) + "there are " + counted(values, "value") + " for " +
                     counted(points, "grid point"));
  }
  if (!marked_inside) throw UsageError(cannot_write(file) + "the marked pose is outside the grid");
}

void check_flags(std::size_t flags, std::size_t points, const fs::path& file) {
  if (flags != 0 && flags != points)
    throw UsageError(cannot_write(file) + "there are " + counted(flags, "flag") + " for " +
                     counted(points, "grid point"));
}

// Called by cairo with pieces of the file; exceptions must not cross its C frames.
cairo_status_t append_bytes(void* closure, const unsigned char* data, unsigned int length) {
  try {
    static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
  } catch (...) {
    return CAIRO_STATUS_WRITE_ERROR;
  }
}

void check_cairo(cairo_status_t status, const fs::path& file) {
  if (status != CAIRO_STATUS_SUCCESS) {
    throw IoError(cannot_write(file) + "drawing failed: " + cairo_status_to_string(status));
  }
}

// The picture, drawn by `draw`, as the bytes of a PNG or SVG file.
std::string render(Format format, const fs::path& file, const std::function<void(cairo_t*)>& draw) {
  std::string bytes;  // declared first: an SVG surface still writes into it when destroyed
  const auto destroy_surface = [](cairo_surface_t* s) { cairo_surface_destroy(s); };
  std::unique_ptr<cairo_surface_t, decltype(destroy_surface)> surface(
      format == Format::png
          ? cairo_image_surface_create(CAIRO_FORMAT_RGB24, image_width, image_height)
          : cairo_svg_surface_create_for_stream(append_bytes, &bytes, image_width, image_height),
      destroy_surface);
  check_cairo(cairo_surface_status(surface.get()), file);
  if (format == Format::svg) cairo_svg_surface_set_document_unit(surface.get(), CAIRO_SVG_UNIT_PX);
  {
    const auto destroy_context = [](cairo_t* cr) { cairo_destroy(cr); };
    std::unique_ptr<cairo_t, decltype(destroy_context)> cr(cairo_create(surface.get()),
                                                           destroy_context);
    set_colour(cr.get(), white);
    cairo_paint(cr.get());
    draw(cr.get());
    check_cairo(cairo_status(cr.get()), file);
  }
  if (format == Format::png) {
    check_cairo(cairo_surface_write_to_png_stream(surface.get(), append_bytes, &bytes), file);
  } else {
    cairo_surface_finish(surface.get());
    check_cairo(cairo_surface_status(surface.get()), file);
  }
  return bytes;
}

}  // namespace

void write_plot(const Heatmap& plot, const std::filesystem::path& file) {
  const Format format = format_of(file);
  check_axis(plot.x, "x", 2, file);
  check_axis(plot.y, "y", 2, file);
  const std::size_t nx = plot.x.values.size();
  const std::size_t ny = plot.y.values.size();
  check_sizes(plot.values.size(), nx * ny,
              !plot.marked || (plot.marked->first < nx && plot.marked->second < ny), file);
  check_flags(plot.flagged.size(), nx * ny, file);
  write_file_atomically(file, render(format, file, [&](cairo_t* cr) { draw_heatmap(cr, plot); }));
}

void write_plot(const LinePlot& plot, const std::filesystem::path& file) {
  const Format format = format_of(file);
  check_axis(plot.x, "x", 1, file);
  check_sizes(plot.values.size(), plot.x.values.size(),
              !plot.marked || *plot.marked < plot.x.values.size(), file);
  check_flags(plot.flagged.size(), plot.x.values.size(), file);
  write_file_atomically(file, render(format, file, [&](cairo_t* cr) { draw_line_plot(cr, plot); }));
}

}  // namespace stiffmsa
