#pragma once
// Link element blocks: 12 equations per link over its two link ends i (from) and j (to),
// d = p_j − p_i and D = [[I, [d×]ᵀ], [0, I]] (paper eq. 2).
#include <optional>

#include "elements/element_block.hpp"

namespace stiffmsa::detail {

// Rigid link, paper eqs. (2), (3):
//   D·Δt_i − Δt_j = 0            (6, compatibility)
//   W_i + Dᵀ·W_j = 0             (6, equilibrium)
// Flexible link with compliance C of end j with end i clamped (global frame):
//   D·Δt_i − Δt_j + C·W_j = 0
//   W_i + Dᵀ·W_j = 0
// This is eq. (1) for the free-free stiffness K12 = [[DᵀKD, −DᵀK], [−KD, K]], K = C⁻¹, with
// the link's own 12 rows combined (rows 1 + Dᵀ·rows 2, and C·rows 2): the same solution, but
// the deflections are no longer recovered from K·Δt differences, which lose about one digit
// per decade of links on a long chain. A rigid link is the case C = 0.
class LinkBlock final : public ElementBlock {
 public:
  LinkBlock(int end_i, int end_j, const Vec3& d, std::optional<Mat6> compliance)
      : end_i_(end_i), end_j_(end_j), d_(d), compliance_(std::move(compliance)) {}
  Index equation_count() const override { return 12; }
  void write_equations(Index first_row, EquationWriter& out) const override;
  // free_free_stiffness(C, d) where the link is flexible.
  std::optional<Mat12> end_stiffness() const override;
  bool has_end_stiffness() const override { return compliance_.has_value(); }
  bool passes_tree() const override { return true; }
  void pass_wrench_to_root(int toward_root, TreeState& state) const override;
  void pass_deflection_from_root(int toward_root, TreeState& state) const override;

 private:
  int end_i_, end_j_;
  Vec3 d_;
  std::optional<Mat6> compliance_;
};

// Paper eq. (1) as printed, [W_i; W_j] − K12·[Δt_i; Δt_j] = 0: for CAD stiffness matrices
// whose clamped-end block K22 is singular, so that no compliance exists.
class StiffnessLinkBlock final : public ElementBlock {
 public:
  StiffnessLinkBlock(int end_i, int end_j, const Mat12& stiffness)
      : end_i_(end_i), end_j_(end_j), stiffness_(stiffness) {}
  Index equation_count() const override { return 12; }
  void write_equations(Index first_row, EquationWriter& out) const override;
  std::optional<Mat12> end_stiffness() const override { return stiffness_; }
  bool has_end_stiffness() const override { return true; }

 private:
  int end_i_, end_j_;
  Mat12 stiffness_;
};

}  // namespace stiffmsa::detail
