#pragma once
#include <optional>

#include "stiffmsa/model.hpp"

namespace stiffmsa::detail {

// A length that makes rotations and translations comparable (the model's extent, at least 1e-3).
double characteristic_length(const Model& model);

// K = C⁻¹, or nullopt where C is singular: the end effector is held rigidly in some direction
// (the smallest eigenvalue of C, rotations weighted by `length`, is below 1e-12 of the largest).
std::optional<Mat6> stiffness_from_compliance(const Mat6& compliance, double length);

}  // namespace stiffmsa::detail
