// The plot module's entry point (src/plot/plot_module.hpp); everything else is hidden.
#include "plot/plot_module.hpp"

extern "C" __attribute__((visibility("default"))) const stiffmsa::detail::PlotModule*
stiffmsa_plot_module() {
  static const stiffmsa::detail::PlotModule module{
      sizeof(stiffmsa::Heatmap), sizeof(stiffmsa::LinePlot),
      [](const stiffmsa::Heatmap& plot, const std::filesystem::path& file) {
        stiffmsa::write_plot(plot, file);
      },
      [](const stiffmsa::LinePlot& plot, const std::filesystem::path& file) {
        stiffmsa::write_plot(plot, file);
      }};
  return &module;
}
