#pragma once
// The free and constrained directions of a joint or support (model-format.md table).
#include "stiffmsa/model.hpp"

namespace stiffmsa::detail {

// Up to 6 rows of 6: held on the stack, as every joint of every pose makes them.
using DirectionRows = Eigen::Matrix<double, Eigen::Dynamic, 6, 0, 6, 6>;
// p×p and p×6 products of them.
using SmallMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;

// Λ_p (p×6, rows in the documented order, custom rows as given) above Λ_r ((6−p)×6,
// orthonormal rows spanning the complement of Λ_p's rows): always 6 rows in all, held in one
// 6×6 matrix, which a rigid connection of a long chain holds as cheaply as a passive joint.
struct FreeDirections {
  Mat6 rows = Mat6::Identity();
  Eigen::Index p = 0;
  auto free() const { return rows.topRows(p); }
  auto constrained() const { return rows.bottomRows(6 - p); }
  // Λ_p·Λ_pᵀ: maps a generalised force along q to its projection Λ_p·w (identity for the
  // built-in types, whose rows are orthonormal).
  SmallMat gram() const { return free() * free().transpose(); }
};

// A spring along the free directions (an elastic joint or support) as a compliance: the motion
// δ with Λ_r·δ = 0 and G·K·Λ_p·δ = Λ_p·w − G·w₀ (`spring` is G·K·Λ_p) is
// δ = compliance·w − preload_motion, compliance = Λ_pᵀ·(G·K·G)⁻¹·Λ_p and preload_motion =
// Λ_pᵀ·(G·K·G)⁻¹·G·w₀ (zero without a preload).
struct SpringCompliance {
  Mat6 compliance;
  Vec6 preload_motion;
};
SpringCompliance spring_compliance(const FreeDirections& directions, const SmallMat& spring,
                                   const std::optional<VecX>& preload);

// Throws InputError (no location) when the kinematics are degenerate; validate() reports the
// same defects with their place in the file before a solve gets here.
FreeDirections free_directions(const Kinematics& kinematics);

// A ball joint that holds the rotation about `axis` (a rod's spin, see SpinLock): the rotations
// about `across`'s part across the axis, then about the axis × that. Turning with the axis
// smoothly from pose to pose, these keep a solver's pivot order good; where `across` is nearly
// along the axis, any two directions across it. The z axis where `axis` is zero (a rod of no
// length spins about every axis through its one point).
FreeDirections rotations_across(const Vec3& axis, const Vec3& across);

// The in-plane axes t1, t2 of a planar joint with normal n (model-format.md).
void planar_axes(const Vec3& normal, Vec3& t1, Vec3& t2);

}  // namespace stiffmsa::detail
