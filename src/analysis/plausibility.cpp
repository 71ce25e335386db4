#include "analysis/plausibility.hpp"

#include <cstdio>

#include "model/value_checks.hpp"
#include "stiffmsa/number_text.hpp"

namespace stiffmsa::detail {

namespace {

// Three significant digits: a size for people, not a value to read back.
std::string rounded(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", value);
  return buffer;
}

// The link end that turns most and the one that moves most, among those determined: link
// ends by id (2·link + end), named only where a warning needs them.
struct LargestDeflection {
  double rotation = 0, translation = 0;
  std::size_t rotation_at = 0, translation_at = 0;

  void consider(std::size_t end, const std::optional<Vec6>& deflection) {
    if (!deflection) return;
    const double turned = deflection->tail<3>().norm(), moved = deflection->head<3>().norm();
    if (turned > rotation) {
      rotation = turned;
      rotation_at = end;
    }
    if (moved > translation) {
      translation = moved;
      translation_at = end;
    }
  }
};

std::string end_name(const Model& model, std::size_t end) {
  return model.links[end / 2].name + (end % 2 == 0 ? ".from" : ".to");
}

}  // namespace

void add_plausibility_warnings(const Model& model, const ModelIndex& index, Result& result) {
  for (const Diagnostic& d : find_implausible_values(model, index))
    result.report.warnings.push_back(d.to_string());

  LargestDeflection largest;
  for (std::size_t l = 0; l < result.links.size(); ++l) {
    largest.consider(2 * l, result.links[l].from.deflection);
    largest.consider(2 * l + 1, result.links[l].to.deflection);
  }
  const double size = result.model_size;
  const bool turns = largest.rotation > kLargestLinearRotation;
  const bool moves = largest.translation > kLargestLinearTranslationFraction * size;
  if (!turns && !moves) return;
  std::string text = std::string(kLargeDeflectionWarning) + ", which assumes small ones:";
  if (turns)
    text += " link end '" + end_name(model, largest.rotation_at) + "' turns " +
            rounded(largest.rotation) + " rad (more than " + shortest_text(kLargestLinearRotation) +
            " rad)";
  if (moves)
    text += std::string(turns ? ";" : "") + " link end '" +
            end_name(model, largest.translation_at) + "' moves " + rounded(largest.translation) +
            " m (more than " + shortest_text(100 * kLargestLinearTranslationFraction) +
            " % of the model's size, " + rounded(size) + " m)";
  text +=
      "; likely a pose near a singularity, loads too large, or a stiffness too small (a modulus in "
      "MPa?)";
  result.report.large_deflection = text;
  result.report.warnings.push_back(std::move(text));
}

}  // namespace stiffmsa::detail
