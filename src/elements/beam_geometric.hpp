#pragma once
// The consistent geometric stiffness of the 3-D beam under an axial force (theory.md §12.4).
// Kernel only: not yet reachable from model files.
#include "elements/beam_element.hpp"

namespace stiffmsa::detail {

// Local 12×12 geometric stiffness, order per end [u, v, w, θx, θy, θz], for the axial force
// `axial_force` (N > 0 tension): the second variation of N·∫(v'² + w'²)/2 dx + N·(r₀²/2)∫θx'² dx
// over the exact shape functions of beam_local_stiffness (Timoshenko's with phi_y, phi_z,
// Euler–Bernoulli's cubics at phi = 0), r₀² = (Iy + Iz)/A the polar radius of gyration.
// Linear in N: K_T = K + K_G(N). Only the axial force's terms: end moments and shears are left out.
Mat12 beam_geometric_stiffness(const BeamConstants& c, double axial_force);

}  // namespace stiffmsa::detail
