#pragma once
// The plot module (target stiffmsa_plot_module): stiffmsa::plot built as a shared module that the
// command loads with dlopen when it draws, so that its other runs do not load cairo and the
// dozens of libraries cairo brings (docs/library.md, "The command's modules").
#include <cstddef>
#include <filesystem>

#include "stiffmsa/io/plot.hpp"

namespace stiffmsa::detail {

inline constexpr const char* kPlotModuleFile = "stiffmsa_plot.so";
inline constexpr const char* kPlotModuleEntry = "stiffmsa_plot_module";

// What the module's entry returns. The sizes tell a module built from other headers (a stale
// install) from this command's, which would otherwise read the structures wrongly.
struct PlotModule {
  std::size_t heatmap_size = sizeof(Heatmap);
  std::size_t line_plot_size = sizeof(LinePlot);
  void (*write_heatmap)(const Heatmap&, const std::filesystem::path&) = nullptr;
  void (*write_line_plot)(const LinePlot&, const std::filesystem::path&) = nullptr;
};

}  // namespace stiffmsa::detail
