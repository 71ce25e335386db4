#pragma once
// What reading a parametric model file binds: each expression written where a number goes,
// with the value slots of the family's structure it fills (Structure::slot_names()). The
// family's writers evaluate the expressions into those slots; tests and tools read the list.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace stiffmsa::detail {

struct ExpressionBinding {
  std::string slot;        // "links.upper.material.E"
  std::string expression;  // as the file writes it
  std::string key;         // the key path where the file writes it: "materials.steel.E"
};

// The bindings of a parametric model file, in slot order, at the parameters' defaults; nullopt
// where the file's members are read from the file each instead, because an expression feeds a
// number that the reader transforms on its way into the model (a robot joint's compliance is
// inverted; a robot's gravity and the loads and offsets on its frames turn with the pose).
// Throws what load_model_family() throws for a file it refuses.
std::optional<std::vector<ExpressionBinding>> expression_bindings(std::string_view text,
                                                                  const std::string& file_name);

}  // namespace stiffmsa::detail
