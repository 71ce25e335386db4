#pragma once
// The load-dependent stiffness of links carried as levers and of joints: what the finite
// rotations of a link's chord and of a joint's free directions do to the wrenches they transmit
// (theory.md §13.2), the ∂(Jᵀ·F)/∂q of the loaded-mode papers written element by element. The
// convention is the beam's geometric stiffness's (beam_geometric.hpp): at the reference wrenches
// the wrenches an element's ends receive change by K_L·Δt beside the linear ones, K_T = K + K_L,
// global axes, deflections of link ends [Δp; Δφ], moments about each end's own point.
#include <vector>

#include "elements/free_directions.hpp"

namespace stiffmsa::detail {

// [a×], a×b = [a×]·b.
Mat3 cross_matrix(const Vec3& a);

// A link whose chord d = p_to − p_from turns: its moment balance about its `from` end,
// M_from + M_to + (d + Δp_to − Δp_from) × F_to = 0, gains the chord's change times the force at
// its `to` end. 12×12 over [Δt_from; Δt_to]; nonzero only in the rows of M_from:
// +[F_to×] under Δp_to, −[F_to×] under Δp_from. The rigid link's whole load-dependent stiffness
// (its chord turns with it); for CAD links the lever's share alone.
Mat12 chord_load_stiffness(const Vec3& force_to);

// A joint of m ends whose free directions turn with its first end's rotation Δφ_1, and whose
// ends part along its free translations: 6m×6m over [Δt_1; …; Δt_m]. `reactions` are the
// wrenches the joint applies to each end at the reference loads (moments about the joint's
// point). End k's rows get P·[[F_k×]; [M_k×]] under Δφ_1, P = Λ_pᵀ·(Λ_p·Λ_pᵀ)⁻¹·Λ_p the
// projection on the free directions (a turned axis sees the turned reaction), and, in its
// moment rows, −[F_k×] under Δp_k and +[F_k×] under Δp_1 (the lever of a slide).
MatX joint_load_stiffness(const FreeDirections& directions, const std::vector<Vec6>& reactions);

}  // namespace stiffmsa::detail
