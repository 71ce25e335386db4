// Plots are checked by what a reader sees: the PNG is read back and its pixels examined (where
// the colour-map ends land, the no-value grey, the marker, which band of the picture each title
// changes), and the SVG for being a complete document drawing the same things.
#include <cairo/cairo.h>
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "stiffmsa/errors.hpp"
#include "stiffmsa/io/plot.hpp"

namespace {

namespace fs = std::filesystem;
using stiffmsa::Heatmap;
using stiffmsa::LinePlot;
using stiffmsa::PlotScale;

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

struct Colour {
  int r, g, b;
};

// The colours the plots promise: the ends and middle of the viridis-like map, the grey for a
// pose without a value, and the line of a line plot.
constexpr Colour low_end{68, 1, 84};
constexpr Colour middle{33, 145, 140};
constexpr Colour high_end{253, 231, 37};
constexpr Colour no_value{191, 191, 191};
constexpr Colour line{31, 95, 168};
constexpr Colour black{0, 0, 0};

bool near(Colour a, Colour b, int tolerance = 2) {
  return std::abs(a.r - b.r) <= tolerance && std::abs(a.g - b.g) <= tolerance &&
         std::abs(a.b - b.b) <= tolerance;
}

struct Box {
  int left, top, right, bottom;  // inclusive
  double centre_x() const { return (left + right) / 2.0; }
  double centre_y() const { return (top + bottom) / 2.0; }
  int width() const { return right - left + 1; }
};

class Image {
 public:
  explicit Image(const fs::path& png) {
    cairo_surface_t* surface = cairo_image_surface_create_from_png(png.c_str());
    if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
      cairo_surface_destroy(surface);
      throw std::runtime_error("cannot read " + png.string());
    }
    width_ = cairo_image_surface_get_width(surface);
    height_ = cairo_image_surface_get_height(surface);
    const int stride = cairo_image_surface_get_stride(surface);
    const unsigned char* data = cairo_image_surface_get_data(surface);
    for (int y = 0; y < height_; ++y) {
      const auto* row = reinterpret_cast<const std::uint32_t*>(data + y * stride);
      pixels_.insert(pixels_.end(), row, row + width_);
    }
    cairo_surface_destroy(surface);
  }

  int width() const { return width_; }
  int height() const { return height_; }
  Colour at(int x, int y) const {
    const std::uint32_t p = pixels_[static_cast<std::size_t>(y) * width_ + x];
    return {static_cast<int>((p >> 16) & 0xff), static_cast<int>((p >> 8) & 0xff),
            static_cast<int>(p & 0xff)};
  }

  // The area covered by solid squares of `colour` of the given side: the inside of cells,
  // never a line, a glyph or the 18-pixel-wide colour bar.
  std::optional<Box> solid_region(Colour colour, int side = 25) const {
    // Summed-area table of matching pixels, so each square is counted in constant time.
    std::vector<int> sums(static_cast<std::size_t>(width_ + 1) * (height_ + 1), 0);
    const auto sum = [&](int x, int y) -> int& {
      return sums[static_cast<std::size_t>(y) * (width_ + 1) + x];
    };
    for (int y = 0; y < height_; ++y) {
      for (int x = 0; x < width_; ++x) {
        sum(x + 1, y + 1) =
            (near(at(x, y), colour) ? 1 : 0) + sum(x, y + 1) + sum(x + 1, y) - sum(x, y);
      }
    }
    std::optional<Box> box;
    for (int y = 0; y + side <= height_; ++y) {
      for (int x = 0; x + side <= width_; ++x) {
        if (sum(x + side, y + side) - sum(x, y + side) - sum(x + side, y) + sum(x, y) !=
            side * side)
          continue;
        if (!box) box = Box{x, y, x + side - 1, y + side - 1};
        box->left = std::min(box->left, x);
        box->top = std::min(box->top, y);
        box->right = std::max(box->right, x + side - 1);
        box->bottom = std::max(box->bottom, y + side - 1);
      }
    }
    return box;
  }

  // Where two pictures differ; nothing when they are the same.
  std::optional<Box> difference(const Image& other) const {
    std::optional<Box> box;
    for (int y = 0; y < height_; ++y) {
      for (int x = 0; x < width_; ++x) {
        if (near(at(x, y), other.at(x, y), 0)) continue;
        if (!box) box = Box{x, y, x, y};
        box->left = std::min(box->left, x);
        box->top = std::min(box->top, y);
        box->right = std::max(box->right, x);
        box->bottom = std::max(box->bottom, y);
      }
    }
    return box;
  }

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<std::uint32_t> pixels_;
};

// Cairo's toy text keeps fonts and fontconfig's patterns for the life of the process, which
// LeakSanitizer (scripts/sanitize.sh) reports as leaks; released here, once no plot is drawn.
// FcFini is looked up at run time: fontconfig is loaded by cairo, but not linked to the test.
class ReleaseFontCaches : public ::testing::Environment {
 public:
  void TearDown() override {
    cairo_debug_reset_static_data();
    if (auto* fc_fini = reinterpret_cast<void (*)()>(dlsym(RTLD_DEFAULT, "FcFini"))) fc_fini();
  }
};
[[maybe_unused]] const auto* const release_font_caches =
    ::testing::AddGlobalTestEnvironment(new ReleaseFontCaches);

// values[iy * nx + ix] over x = 0, 1, ... and y = 0, 1, ...
Heatmap heatmap(std::size_t nx, std::size_t ny, std::vector<double> values) {
  Heatmap plot;
  plot.title = "Stiffness map";
  plot.x = {"x", "m", {}};
  plot.y = {"y", "m", {}};
  for (std::size_t i = 0; i < nx; ++i) plot.x.values.push_back(static_cast<double>(i));
  for (std::size_t i = 0; i < ny; ++i) plot.y.values.push_back(static_cast<double>(i));
  plot.quantity = "k_min";
  plot.unit = "N/m";
  plot.values = std::move(values);
  return plot;
}

// 0 at the lower left, 8 at the upper right.
Heatmap counting_heatmap() { return heatmap(3, 3, {0, 1, 2, 3, 4, 5, 6, 7, 8}); }

LinePlot line_plot(std::vector<double> values) {
  LinePlot plot;
  plot.title = "Stiffness along x";
  plot.x = {"x", "m", {}};
  for (std::size_t i = 0; i < values.size(); ++i) plot.x.values.push_back(static_cast<double>(i));
  plot.quantity = "k_min";
  plot.unit = "N/m";
  plot.values = std::move(values);
  return plot;
}

class Plot : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    folder_ = fs::temp_directory_path() /
              ("stiffmsa-test-plot-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  template <typename P>
  Image drawn(const P& plot, const std::string& name = "plot.png") {
    const fs::path file = folder_ / name;
    stiffmsa::write_plot(plot, file);
    return Image(file);
  }

  static std::string read(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return bytes.str();
  }

  bool folder_is_empty() const { return fs::is_empty(folder_); }

  fs::path folder_;
};

std::uint32_t big_endian(const std::string& bytes, std::size_t at) {
  std::uint32_t value = 0;
  for (std::size_t i = 0; i < 4; ++i)
    value = (value << 8) | static_cast<unsigned char>(bytes[at + i]);
  return value;
}

std::size_t count(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

// ---- PNG ------------------------------------------------------------------------------------

TEST_F(Plot, PngHasTheSignatureAndIsAbout800By600) {
  const fs::path file = folder_ / "map.png";
  stiffmsa::write_plot(counting_heatmap(), file);
  const std::string bytes = read(file);
  ASSERT_GT(bytes.size(), 24u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(bytes.substr(12, 4), "IHDR");
  EXPECT_EQ(big_endian(bytes, 16), 800u);
  EXPECT_EQ(big_endian(bytes, 20), 600u);
}

TEST_F(Plot, MinimumCellHasTheLowEndColourAndMaximumTheHighEndWithYGrowingUpward) {
  const Image image = drawn(counting_heatmap());
  const auto low = image.solid_region(low_end);
  const auto mid = image.solid_region(middle);
  const auto high = image.solid_region(high_end);
  ASSERT_TRUE(low && mid && high);
  EXPECT_TRUE(near(image.at(static_cast<int>(low->centre_x()), static_cast<int>(low->centre_y())),
                   low_end));
  // Value 0 sits at x = 0, y = 0: left and at the bottom; value 8 right and at the top.
  EXPECT_LT(low->centre_x(), high->centre_x());
  EXPECT_GT(low->centre_y(), high->centre_y());
  // Equal cells on an even grid: the middle value's cell is centred between the two.
  EXPECT_NEAR(mid->centre_x(), (low->centre_x() + high->centre_x()) / 2, 1.5);
  EXPECT_NEAR(mid->centre_y(), (low->centre_y() + high->centre_y()) / 2, 1.5);
  EXPECT_NEAR(mid->width(), low->width(), 2);
}

TEST_F(Plot, CellsAreCentredOnTheirCoordinatesAndReachHalfwayToTheirNeighbours) {
  // x = 0, 1, 3: cells [-0.5, 0.5], [0.5, 2], [2, 4], widths 1 : 1.5 : 2.
  Heatmap plot = heatmap(3, 2, {0, 4, 8, 0, 4, 8});
  plot.x.values = {0, 1, 3};
  const Image image = drawn(plot);
  const auto first = image.solid_region(low_end);
  const auto second = image.solid_region(middle);
  const auto third = image.solid_region(high_end);
  ASSERT_TRUE(first && second && third);
  EXPECT_NEAR(static_cast<double>(second->width()) / first->width(), 1.5, 0.04);
  EXPECT_NEAR(static_cast<double>(third->width()) / first->width(), 2.0, 0.05);
  EXPECT_LE(std::abs(second->left - first->right), 2);
  EXPECT_LE(std::abs(third->left - second->right), 2);
}

TEST_F(Plot, LogarithmicScaleColoursByDecade) {
  // 1 to 10000: 100 is half way in decades, but near the bottom on a linear scale.
  Heatmap plot = heatmap(2, 2, {1, 10, 100, 10000});
  plot.scale = PlotScale::logarithmic;
  const Image log_image = drawn(plot, "log.png");
  EXPECT_TRUE(log_image.solid_region(low_end));
  EXPECT_TRUE(log_image.solid_region(middle));
  EXPECT_TRUE(log_image.solid_region(high_end));
  plot.scale = PlotScale::linear;
  const Image linear_image = drawn(plot, "linear.png");
  EXPECT_FALSE(linear_image.solid_region(middle));
}

TEST_F(Plot, NaNCellIsNoValueGreyAndNamedInALegendOnlyThen) {
  const Image with_gap = drawn(heatmap(3, 2, {1, 2, 3, 4, nan, 6}), "gap.png");
  const auto cell = with_gap.solid_region(no_value);
  ASSERT_TRUE(cell);
  const auto low = with_gap.solid_region(low_end);
  ASSERT_TRUE(low);
  EXPECT_GT(cell->centre_x(), low->centre_x());  // the middle column ...
  EXPECT_LT(cell->centre_y(), low->centre_y());  // ... of the upper row
  // The legend's swatch: grey below the plot.
  const auto swatch = with_gap.solid_region(no_value, 8);
  ASSERT_TRUE(swatch);
  EXPECT_GT(swatch->bottom, low->bottom + 30);

  const Image complete = drawn(heatmap(3, 2, {1, 2, 3, 4, 5, 6}), "complete.png");
  EXPECT_FALSE(complete.solid_region(no_value, 8));
}

TEST_F(Plot, NonPositiveValuesOnALogScaleHaveNoValue) {
  Heatmap plot = heatmap(2, 2, {0, -1, 10, 100});
  plot.scale = PlotScale::logarithmic;
  const Image image = drawn(plot);
  EXPECT_TRUE(image.solid_region(no_value));
  EXPECT_TRUE(image.solid_region(low_end));
  EXPECT_TRUE(image.solid_region(high_end));
}

TEST_F(Plot, ConstantAndAllMissingMapsStillDraw) {
  const Image constant = drawn(heatmap(2, 2, {5, 5, 5, 5}), "constant.png");
  EXPECT_EQ(constant.width(), 800);
  EXPECT_TRUE(constant.solid_region(middle));
  Heatmap log_constant = heatmap(2, 2, {5, 5, 5, 5});
  log_constant.scale = PlotScale::logarithmic;
  EXPECT_TRUE(drawn(log_constant, "log-constant.png").solid_region(middle));
  const Image missing = drawn(heatmap(2, 2, {nan, nan, nan, nan}), "missing.png");
  EXPECT_TRUE(missing.solid_region(no_value));
  EXPECT_FALSE(missing.solid_region(low_end));
}

TEST_F(Plot, MarkedPoseHasAMarkerOnTheCellCentreAndItsLabelInsideThePlot) {
  Heatmap plot = counting_heatmap();
  const Image plain = drawn(plot, "plain.png");
  const auto cell = plain.solid_region(high_end);  // {2, 2}: upper right, next to the bar
  ASSERT_TRUE(cell);
  const int x = static_cast<int>(std::lround(cell->centre_x()));
  const int y = static_cast<int>(std::lround(cell->centre_y()));

  plot.marked = {{2, 2}};
  const Image marked = drawn(plot, "marked.png");
  EXPECT_TRUE(near(plain.at(x, y), high_end));
  EXPECT_TRUE(near(marked.at(x, y), black, 60));

  plot.marked_label = "softest: 8 N/m";
  const Image labelled = drawn(plot, "labelled.png");
  const auto label = labelled.difference(marked);
  ASSERT_TRUE(label);
  // Inside the plot: between the lower left and upper right cells.
  const auto low = plain.solid_region(low_end);
  ASSERT_TRUE(low);
  EXPECT_GE(label->left, low->left);
  EXPECT_LE(label->right, cell->right);
  EXPECT_GE(label->top, cell->top);
  EXPECT_LE(label->bottom, low->bottom);
}

TEST_F(Plot, EachTitleIsDrawnInItsOwnPlace) {
  const Heatmap base = counting_heatmap();
  const Image reference = drawn(base, "reference.png");
  const auto low = reference.solid_region(low_end);    // lower left cell
  const auto high = reference.solid_region(high_end);  // upper right cell
  ASSERT_TRUE(low && high);

  const auto changed = [&](const std::function<void(Heatmap&)>& change) {
    Heatmap plot = base;
    change(plot);
    return drawn(plot, "changed.png").difference(reference);
  };
  const auto title = changed([](Heatmap& p) { p.title = "Minimum translational stiffness"; });
  ASSERT_TRUE(title);
  EXPECT_LT(title->bottom, high->top);
  const auto x_title = changed([](Heatmap& p) { p.x.name = "position along x"; });
  ASSERT_TRUE(x_title);
  EXPECT_GT(x_title->top, low->bottom);
  const auto y_title = changed([](Heatmap& p) { p.y.unit = "mm"; });
  ASSERT_TRUE(y_title);
  EXPECT_LT(y_title->right, low->left);
  const auto bar_title = changed([](Heatmap& p) { p.unit = "kN/m"; });
  ASSERT_TRUE(bar_title);
  EXPECT_GT(bar_title->left, high->right);
}

// ---- SVG ------------------------------------------------------------------------------------

TEST_F(Plot, SvgIsACompleteDocumentOfTheSameDrawing) {
  const fs::path file = folder_ / "map.svg";
  stiffmsa::write_plot(heatmap(3, 2, {1, 2, 3, 4, nan, 6}), file);
  std::string svg = read(file);
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("width=\"800px\" height=\"600px\""), std::string::npos);
  while (!svg.empty() && std::isspace(static_cast<unsigned char>(svg.back()))) svg.pop_back();
  EXPECT_TRUE(svg.ends_with("</svg>"));
  // Cairo writes colours as percentages: the low end (68, 1, 84) and the no-value grey.
  EXPECT_NE(svg.find("fill:rgb(26.666667%,0.392157%,32.941176%)"), std::string::npos);
  EXPECT_NE(svg.find("fill:rgb(74.901961%,74.901961%,74.901961%)"), std::string::npos);
}

TEST_F(Plot, SvgTextIsDrawnGlyphByGlyph) {
  // Cairo's SVG has no searchable text: each character of the title is one placed glyph.
  Heatmap plot = counting_heatmap();
  plot.title = "";
  stiffmsa::write_plot(plot, folder_ / "untitled.svg");
  plot.title = "Kxyz";
  stiffmsa::write_plot(plot, folder_ / "titled.svg");
  const std::string glyph = "<use xlink:href=\"#glyph";
  EXPECT_EQ(count(read(folder_ / "titled.svg"), glyph),
            count(read(folder_ / "untitled.svg"), glyph) + 4);
}

// ---- Line plots -----------------------------------------------------------------------------

// The widest run of picture columns without the line's colour between its first and last.
int widest_gap_in_line(const Image& image) {
  std::vector<bool> has_line(image.width(), false);
  for (int x = 0; x < image.width(); ++x) {
    for (int y = 0; y < image.height() && !has_line[x]; ++y)
      has_line[x] = near(image.at(x, y), line, 10);
  }
  const auto first = std::find(has_line.begin(), has_line.end(), true);
  const auto last = std::find(has_line.rbegin(), has_line.rend(), true).base();
  int widest = 0;
  int run = 0;
  for (auto it = first; it < last; ++it) {
    run = *it ? 0 : run + 1;
    widest = std::max(widest, run);
  }
  return first == has_line.end() ? -1 : widest;
}

TEST_F(Plot, LinePlotLeavesAGapWhereValuesAreMissing) {
  std::vector<double> values;
  for (int i = 0; i <= 20; ++i) values.push_back(1 + 0.1 * i * i);
  const Image complete = drawn(line_plot(values), "complete.png");
  EXPECT_EQ(complete.width(), 800);
  EXPECT_GE(widest_gap_in_line(complete), 0);
  EXPECT_LT(widest_gap_in_line(complete), 5);
  for (int i = 8; i <= 12; ++i) values[i] = nan;
  LinePlot gappy = line_plot(values);
  gappy.scale = PlotScale::logarithmic;
  EXPECT_GT(widest_gap_in_line(drawn(gappy, "gappy.png")), 80);
}

TEST_F(Plot, LinePlotMarksThePoint) {
  LinePlot plot = line_plot({3, 2, 1, 2, 3});
  const Image plain = drawn(plot, "plain.png");
  plot.marked = 2;
  plot.marked_label = "softest: 1 N/m";
  const Image marked = drawn(plot, "marked.png");
  const auto marker = marked.difference(plain);
  ASSERT_TRUE(marker);
  // The marked value is the smallest: the lowest dot of the line, covered by the marker.
  int dot_x = 0;
  int dot_y = 0;
  for (int y = 0; y < plain.height(); ++y) {
    for (int x = 0; x < plain.width(); ++x) {
      if (near(plain.at(x, y), line, 10)) std::tie(dot_x, dot_y) = std::pair{x, y};
    }
  }
  dot_y -= 2;  // from the dot's edge to its centre
  EXPECT_GT(dot_y, plain.height() / 2);
  EXPECT_TRUE(dot_x >= marker->left && dot_x <= marker->right && dot_y >= marker->top &&
              dot_y <= marker->bottom);
  EXPECT_TRUE(near(marked.at(dot_x, dot_y), black, 60));
}

TEST_F(Plot, LinePlotOfOnePointIsDrawn) {
  const Image image = drawn(line_plot({42}), "one.png");
  EXPECT_EQ(image.height(), 600);
  EXPECT_EQ(widest_gap_in_line(image), 0);  // the dot
}

// ---- Errors ---------------------------------------------------------------------------------

TEST_F(Plot, UnknownExtensionIsAUsageErrorNamingTheFile) {
  const fs::path file = folder_ / "map.jpg";
  try {
    stiffmsa::write_plot(counting_heatmap(), file);
    FAIL() << "expected UsageError";
  } catch (const stiffmsa::UsageError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_NE(message.find(".png or .svg"), std::string::npos) << message;
  }
  EXPECT_THROW(stiffmsa::write_plot(line_plot({1, 2}), folder_ / "plot"), stiffmsa::UsageError);
  EXPECT_TRUE(folder_is_empty());
  stiffmsa::write_plot(line_plot({1, 2}), folder_ / "PLOT.PNG");  // case does not matter
}

TEST_F(Plot, MismatchedOrUnusableDataAreUsageErrors) {
  const fs::path file = folder_ / "map.png";
  Heatmap short_values = counting_heatmap();
  short_values.values.pop_back();
  EXPECT_THROW(stiffmsa::write_plot(short_values, file), stiffmsa::UsageError);
  Heatmap outside = counting_heatmap();
  outside.marked = {{3, 0}};
  EXPECT_THROW(stiffmsa::write_plot(outside, file), stiffmsa::UsageError);
  outside.marked = {{0, 3}};
  EXPECT_THROW(stiffmsa::write_plot(outside, file), stiffmsa::UsageError);
  EXPECT_THROW(stiffmsa::write_plot(heatmap(1, 3, {1, 2, 3}), file), stiffmsa::UsageError);
  Heatmap descending = counting_heatmap();
  descending.y.values = {0, 2, 1};
  EXPECT_THROW(stiffmsa::write_plot(descending, file), stiffmsa::UsageError);
  Heatmap repeated = counting_heatmap();
  repeated.x.values = {0, 1, 1};
  EXPECT_THROW(stiffmsa::write_plot(repeated, file), stiffmsa::UsageError);

  LinePlot too_many = line_plot({1, 2, 3});
  too_many.values.push_back(4);
  EXPECT_THROW(stiffmsa::write_plot(too_many, file), stiffmsa::UsageError);
  LinePlot marked_outside = line_plot({1, 2, 3});
  marked_outside.marked = 3;
  EXPECT_THROW(stiffmsa::write_plot(marked_outside, file), stiffmsa::UsageError);
  EXPECT_THROW(stiffmsa::write_plot(line_plot({}), file), stiffmsa::UsageError);
  EXPECT_TRUE(folder_is_empty());
}

TEST_F(Plot, FailedWriteIsAnIoErrorAndLeavesNoFile) {
  const fs::path file = folder_ / "no-such-folder" / "map.png";
  EXPECT_THROW(stiffmsa::write_plot(counting_heatmap(), file), stiffmsa::IoError);
  EXPECT_THROW(stiffmsa::write_plot(line_plot({1, 2}), folder_ / "no-such-folder" / "line.svg"),
               stiffmsa::IoError);
  EXPECT_FALSE(fs::exists(file));
  EXPECT_TRUE(folder_is_empty());
}

}  // namespace

// ---- subtitles and flagged poses (issue 18) ----------------------------------------------------

TEST_F(Plot, SubtitleIsALineUnderTheTitleAndThePlotMovesDownForIt) {
  const Heatmap base = counting_heatmap();
  const Image reference = drawn(base, "reference.png");
  Heatmap with_subtitle = base;
  with_subtitle.subtitle = "at pz = 0.15 m (set); under F (0, 0, -100) N at platform";
  const Image subtitled = drawn(with_subtitle, "subtitled.png");
  const auto high = reference.solid_region(high_end);
  const auto moved = subtitled.solid_region(high_end);
  ASSERT_TRUE(high && moved);
  EXPECT_GT(moved->top, high->top);
  // Dark glyphs in the band between the title and the (moved) plot, where the plain plot is white.
  int dark_in_band = 0, dark_before = 0;
  for (int y = 38; y < moved->top - 8; ++y)
    for (int x = 0; x < subtitled.width(); ++x) {
      dark_in_band += near(subtitled.at(x, y), black, 100) ? 1 : 0;
      dark_before += near(reference.at(x, y), black, 100) && y < high->top - 8 ? 1 : 0;
    }
  EXPECT_GT(dark_in_band, 50);
  EXPECT_EQ(dark_before, 0);
}

TEST_F(Plot, FlaggedCellsHaveARingThatLeavesTheirColourVisibleAndALegend) {
  Heatmap plot = counting_heatmap();
  const Image plain = drawn(plot, "plain.png");
  plot.flagged.assign(9, false);
  plot.flagged[8] = true;  // the upper right cell
  plot.flagged_label = "deflections beyond the linear method's range";
  const Image flagged = drawn(plot, "flagged.png");
  const auto cell = flagged.solid_region(high_end, 10);
  ASSERT_TRUE(cell);
  const int x = static_cast<int>(std::lround(cell->centre_x()));
  const int y = static_cast<int>(std::lround(cell->centre_y()));
  EXPECT_TRUE(near(flagged.at(x, y), high_end));  // the colour inside the ring
  // The ring, 6 pixels from the centre of a large cell, on either side.
  EXPECT_TRUE(near(flagged.at(x + 6, y), black, 80) || near(flagged.at(x + 7, y), black, 80));
  EXPECT_TRUE(near(flagged.at(x - 6, y), black, 80) || near(flagged.at(x - 7, y), black, 80));
  // The lower left cell has none: its centre row is the map's colour throughout.
  const auto low = flagged.solid_region(low_end, 10);
  ASSERT_TRUE(low);
  for (int dx = -8; dx <= 8; ++dx)
    EXPECT_TRUE(
        near(flagged.at(static_cast<int>(low->centre_x()) + dx, static_cast<int>(low->centre_y())),
             low_end));
  // A legend line under the plot, which the plain map does not have.
  const auto plain_low = plain.solid_region(low_end);
  ASSERT_TRUE(plain_low);
  EXPECT_LT(low->bottom, plain_low->bottom);  // the plot shrank to make room for it

  plot.flagged.assign(3, true);
  EXPECT_THROW(drawn(plot, "mismatched.png"), stiffmsa::UsageError);
}

TEST_F(Plot, LinePlotRingsItsFlaggedPoints) {
  LinePlot plot = line_plot({1, 2, 3, 4});
  plot.flagged_label = "large deflections";
  plot.flagged = {true, false, false, false};
  const Image one = drawn(plot, "one.png");
  plot.flagged = {true, false, true, false};
  const Image two = drawn(plot, "two.png");
  // The same layout (both have the legend): they differ by one ring, small and around the third
  // point, right of the middle and above it (values rise to the right).
  const auto ring = two.difference(one);
  ASSERT_TRUE(ring);
  EXPECT_LE(ring->width(), 16);
  EXPECT_LE(ring->bottom - ring->top + 1, 16);
  EXPECT_GT(ring->centre_x(), two.width() / 2.0);
  EXPECT_LT(ring->centre_y(), two.height() / 2.0);
  bool any_black = false;
  for (int y = ring->top; y <= ring->bottom; ++y)
    for (int x = ring->left; x <= ring->right; ++x)
      any_black = any_black || near(two.at(x, y), black, 60);
  EXPECT_TRUE(any_black);
}
