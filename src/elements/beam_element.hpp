#pragma once
// The 3-D frame element (sections.md "Element matrices") and the local axes of a link.
#include <optional>

#include "stiffmsa/model.hpp"

namespace stiffmsa::detail {

// Rows are the local x, y, z axes in global coordinates (model-format.md "Beam axes").
// Throws InputError when zref is parallel to the link.
Mat3 link_axes(const Vec3& from, const Vec3& to, const std::optional<Vec3>& zref);

// T = diag(R, R, R, R): maps global 12-vectors [Δt_from; Δt_to] to local ones.
Mat12 link_rotation12(const Mat3& axes);

struct BeamConstants {
  double length = 0;
  double E = 0, G = 0;
  double A = 0, Iy = 0, Iz = 0, J = 0;
  double phi_y = 0;  // 12·E·Iz/(G·Asy·L²), bending in the x-y plane; 0 for Euler–Bernoulli
  double phi_z = 0;  // 12·E·Iy/(G·Asz·L²), bending in the x-z plane
};

BeamConstants beam_constants(const BeamLink& beam, double length);

// Local free-free stiffness, order per end [u, v, w, θx, θy, θz].
Mat12 beam_local_stiffness(const BeamConstants& c);

// Global 12×12 free-free stiffness of a beam link between two points.
Mat12 beam_global_stiffness(const BeamLink& beam, const Vec3& from, const Vec3& to);

// Compliance of the `to` end with the `from` end clamped, local axes: the inverse of the
// stiffness's `to` block, written in closed form so that no inversion rounds it.
Mat6 beam_local_compliance(const BeamConstants& c);

// The same in global axes.
Mat6 beam_global_compliance(const BeamLink& beam, const Vec3& from, const Vec3& to);

// diag(R, R) for a 3×3 rotation R.
Mat6 rotation6(const Mat3& axes);

}  // namespace stiffmsa::detail
