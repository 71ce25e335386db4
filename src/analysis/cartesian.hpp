#pragma once
#include <optional>

#include "stiffmsa/model.hpp"

namespace stiffmsa::detail {

// A length that makes rotations and translations comparable (the model's extent, at least 1e-3).
double characteristic_length(const Model& model);

// K = C⁻¹, or nullopt where C is singular: the end effector is held rigidly in some direction
// (the smallest eigenvalue of C, rotations weighted by `length`, is below 1e-14 of the largest:
// rounding level, where a rigid hold and an extreme near-mechanism look alike).
std::optional<Mat6> stiffness_from_compliance(const Mat6& compliance, double length);

// Largest over smallest eigenvalue of a compliance with rotations weighted by `length`: how many
// decades the end effector's stiffness spans across directions (+inf where some direction is
// held rigidly).
double compliance_spread(const Mat6& compliance, double length);

}  // namespace stiffmsa::detail
