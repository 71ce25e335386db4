// libFuzzer target for the model loader: any bytes go to parse_model(); a model that parses is
// checked and, when small, solved, and its result goes through what `stiffmsa solve` prints
// (principal stiffnesses, the result JSON); the messages of rejected input are formatted. Every
// stiffmsa::Error (InputError, SingularModelError, IoError, UsageError) is an expected outcome for
// hostile input. Anything else is a finding: a crash, a sanitizer report, a hang or out-of-memory,
// or an exception that is not a stiffmsa::Error (the library documents only those), which escapes
// and aborts the fuzzer.
//
// Build and run with scripts/fuzz.sh.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "stiffmsa/analysis.hpp"
#include "stiffmsa/errors.hpp"
#include "stiffmsa/io/model_file.hpp"
#include "stiffmsa/io/result_file.hpp"
#include "stiffmsa/model.hpp"
#include "stiffmsa/parametric.hpp"

namespace {

// Larger models are only parsed and checked, so that one execution stays fast.
constexpr std::size_t kMaxSolvedEntities = 50;

bool small_enough_to_solve(const stiffmsa::Model& model) {
  return model.links.size() <= kMaxSolvedEntities && model.points.size() <= kMaxSolvedEntities &&
         model.joints.size() <= kMaxSolvedEntities && model.supports.size() <= kMaxSolvedEntities &&
         model.loads.size() <= kMaxSolvedEntities &&
         model.end_effectors.size() <= kMaxSolvedEntities;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const stiffmsa::Model model = stiffmsa::parse_model(text, "fuzz.yaml");
    stiffmsa::check(model);
    if (small_enough_to_solve(model)) {
      const stiffmsa::Result result = stiffmsa::solve(model);
      for (const auto& e : result.end_effectors)
        if (e.compliance) static_cast<void>(stiffmsa::principal_stiffness(*e.compliance));
      static_cast<void>(stiffmsa::result_to_json(result));
    }
    // A parametric file also as a family: binding its expressions, and one member away from
    // the defaults (the values that fail are the documented InputError).
    if (text.find("parameters") == std::string_view::npos &&
        text.find("derived") == std::string_view::npos)
      return 0;
    const stiffmsa::ModelFamily family = stiffmsa::parse_model_family(text, "fuzz.yaml");
    if (!family.parameters().empty()) {
      std::vector<double> values = family.default_values();
      for (double& v : values) v = v * 1.25 + 0.5;
      static_cast<void>(stiffmsa::check(family.build(values)));
    }
  } catch (const stiffmsa::InputError& e) {
    for (const auto& d : e.diagnostics()) static_cast<void>(d.to_string());
  } catch (const stiffmsa::Error&) {
    // Rejected input or a singular model: the documented outcome.
  }
  return 0;
}
