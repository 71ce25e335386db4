#pragma once
#include <optional>

#include "stiffmsa/result.hpp"

namespace stiffmsa::detail {

// A length that makes rotations and translations comparable (the model's extent, at least 1e-3).
double characteristic_length(const Model& model);

// The end effector's stiffness from its compliance C, with rotations weighted by `length` in
// Ĉ, the symmetric part of the weighted C, for its checks. Where a Cholesky factorisation of Ĉ
// bounds its eigenvalue spread by tr(Ĉ)·tr(Ĉ⁻¹) (at most 36 times the spread) to at most
// `spread_threshold` and 1e14, no check can fire and K = C⁻¹ by a partially pivoted LU;
// elsewhere the eigenvalues of Ĉ measure the spread exactly, and K = C⁻¹ by a fully pivoted LU.
struct CartesianStiffness {
  // K = C⁻¹, or nullopt where C is singular: the end effector is held rigidly in some direction
  // (the smallest eigenvalue is below 1e-14 of the largest: rounding level, where a rigid hold
  // and an extreme near-mechanism look alike).
  std::optional<Mat6> stiffness;
  // Largest over smallest eigenvalue: how many decades the stiffness spans across directions
  // (+inf where some direction is held rigidly). Exact where it may exceed `spread_threshold`;
  // below it, the bound that showed it does not.
  double spread = 0;
};
CartesianStiffness cartesian_stiffness(const Mat6& compliance, double length,
                                       double spread_threshold);

// Where the compliance holds some directions rigidly (the same test as above: eigenvalues of Ĉ
// within 1e-14 of the largest), the stiffness on the others; nullopt where no direction or
// every direction is held.
std::optional<ReducedStiffness> reduced_stiffness(const Mat6& compliance, double length);

}  // namespace stiffmsa::detail
