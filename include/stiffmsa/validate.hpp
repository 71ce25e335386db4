#pragma once
#include "stiffmsa/model.hpp"

namespace stiffmsa {

// Every defect of a model that can be found without solving it (names, references, geometry,
// section and material values, joint axes, matrix properties, connection rules), in model
// order. Empty when the model is valid.
std::vector<Diagnostic> find_defects(const Model& model);

// Values of a valid model that are unlike those of real structures in SI units and more
// likely a slip of units: a modulus outside the range of engineering materials, a model so
// large or a beam section so wide for its length that it suggests millimetres
// (docs/model-format.md, "Plausibility warnings"). Warnings, never errors: a model may mean
// them. A value shared by several links is one warning that counts them.
std::vector<Diagnostic> find_implausible_values(const Model& model);

// Throws InputError listing every defect found by find_defects().
void validate(const Model& model);

}  // namespace stiffmsa
