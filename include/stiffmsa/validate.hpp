#pragma once
#include "stiffmsa/model.hpp"

namespace stiffmsa {

// Every defect of a model that can be found without solving it (names, references, geometry,
// section and material values, joint axes, matrix properties, connection rules), in model
// order. Empty when the model is valid.
std::vector<Diagnostic> find_defects(const Model& model);

// Throws InputError listing every defect found by find_defects().
void validate(const Model& model);

}  // namespace stiffmsa
