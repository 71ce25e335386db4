#pragma once
// Warnings for results that are valid but unlike a real structure's (docs/model-format.md,
// "Plausibility warnings"): the model's implausible values, and deflections beyond the range
// where the linear method holds.
#include "model/link_ends.hpp"
#include "stiffmsa/model.hpp"
#include "stiffmsa/result.hpp"

namespace stiffmsa::detail {

// The linear method of MSA holds while rotations are small (sin θ and θ differ by 0.04 % at
// 0.05 rad) and translations are small against the structure's size.
constexpr double kLargestLinearRotation = 0.05;             // rad
constexpr double kLargestLinearTranslationFraction = 0.03;  // of the model's size

// Appends to the report's warnings those of find_implausible_values() and, where some link
// end's deflection under the loads is beyond the linear range, one naming the largest
// (also kept in SolveReport::large_deflection), measured against Result::model_size.
void add_plausibility_warnings(const Model& model, const ModelIndex& index, Result& result);

}  // namespace stiffmsa::detail
