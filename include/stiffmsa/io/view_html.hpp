#pragma once
// The model viewer: one self-contained HTML page (three.js inside it, nothing loaded from
// outside) that draws a model in 3-D with its deformed shape under the loads and the compliance
// or stiffness ellipsoid of each end effector (docs/viewer.md). Every name and text from the
// model reaches the page as JSON data, shown as text only.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "stiffmsa/model.hpp"
#include "stiffmsa/result.hpp"

namespace stiffmsa {

struct ModelViewOptions {
  // Magnification of the deformed shape; default: the largest displacement drawn as a tenth of
  // the model's size.
  std::optional<double> scale;
  // The parameters' values of a parametric model, shown under the title: "name = value unit".
  std::vector<std::string> parameters;
  // Why there is no result (a mechanism, say): shown in place of the deformed shape.
  std::string not_solved;
  // Segments per beam for the deformed shape; default: fewer as the model grows, so that the
  // page stays small (8 for a robot, 1 for a 100 000-link chain).
  std::optional<int> beam_segments;
};

// The page for a validated model and its result (nullptr: the model only). Throws UsageError
// for a scale that is not positive and finite.
std::string model_view_html(const Model& model, const Result* result,
                            const ModelViewOptions& options = {});

// Writes that page whole or not at all. Throws IoError.
void write_model_view(const Model& model, const Result* result, const ModelViewOptions& options,
                      const std::filesystem::path& file);

// Text made safe inside a <script type="application/json"> block: '<', '>' and '&' as JSON
// escapes, so that no text from a model can end the block or open a tag.
std::string json_for_script_block(const std::string& json);

}  // namespace stiffmsa
