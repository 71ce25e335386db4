// stiffmsa::write_plot for the command: forwarded to the plot module, loaded when the first plot
// is drawn (src/plot/plot_module.hpp), so that the command itself links no cairo.
#include "module_loader.hpp"
#include "plot/plot_module.hpp"
#include "stiffmsa/errors.hpp"

namespace stiffmsa {

namespace {

const detail::PlotModule& plot_module() {
  using Entry = const detail::PlotModule* (*)();
  const auto entry = reinterpret_cast<Entry>(cli::module_entry(
      detail::kPlotModuleFile, detail::kPlotModuleEntry, "the plot module (--plot)"));
  const detail::PlotModule* module = entry();
  if (module->heatmap_size != sizeof(Heatmap) || module->line_plot_size != sizeof(LinePlot))
    throw IoError("the plot module was built from another version of stiffmsa than this command");
  return *module;
}

}  // namespace

void write_plot(const Heatmap& plot, const std::filesystem::path& file) {
  plot_module().write_heatmap(plot, file);
}

void write_plot(const LinePlot& plot, const std::filesystem::path& file) {
  plot_module().write_line_plot(plot, file);
}

}  // namespace stiffmsa
