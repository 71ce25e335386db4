#pragma once
#include <optional>

#include "stiffmsa/model.hpp"

namespace stiffmsa::detail {

// A length that makes rotations and translations comparable (the model's extent, at least 1e-3).
double characteristic_length(const Model& model);

// The end effector's stiffness from its compliance C, with one eigen-decomposition of C
// (rotations weighted by `length`) for both of its checks:
struct CartesianStiffness {
  // K = C⁻¹, or nullopt where C is singular: the end effector is held rigidly in some direction
  // (the smallest eigenvalue is below 1e-14 of the largest: rounding level, where a rigid hold
  // and an extreme near-mechanism look alike).
  std::optional<Mat6> stiffness;
  // Largest over smallest eigenvalue: how many decades the stiffness spans across directions
  // (+inf where some direction is held rigidly).
  double spread = 0;
};
CartesianStiffness cartesian_stiffness(const Mat6& compliance, double length);

}  // namespace stiffmsa::detail
