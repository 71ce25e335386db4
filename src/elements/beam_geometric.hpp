#pragma once
// The consistent geometric stiffness of the 3-D beam under an axial force (theory.md §12.4),
// used by the critical load factor (theory.md §13).
#include "elements/beam_element.hpp"

namespace stiffmsa::detail {

// Local 12×12 geometric stiffness, order per end [u, v, w, θx, θy, θz], for the axial force
// `axial_force` (N > 0 tension): the second variation of N·∫(v'² + w'²)/2 dx + N·(r₀²/2)∫θx'² dx
// over the exact shape functions of beam_local_stiffness (Timoshenko's with phi_y, phi_z,
// Euler–Bernoulli's cubics at phi = 0), r₀² = (Iy + Iz)/A the polar radius of gyration.
// Linear in N: K_T = K + K_G(N). Only the axial force's terms: end moments and shears are left out.
Mat12 beam_geometric_stiffness(const BeamConstants& c, double axial_force);

// The same in global axes, over [Δt_from; Δt_to]: Tᵀ·K_G·T with the beam's local axes.
Mat12 beam_global_geometric_stiffness(const BeamLink& beam, const Vec3& from, const Vec3& to,
                                      double axial_force);

// The axial force of a beam (N > 0 tension) from the forces applied to it at its ends (global
// axes): the mean of F_to·x and −F_from·x, x the unit vector from `from` to `to` (the two are
// equal where nothing acts along the beam).
double beam_axial_force(const Vec3& from, const Vec3& to, const Vec3& force_from,
                        const Vec3& force_to);

}  // namespace stiffmsa::detail
