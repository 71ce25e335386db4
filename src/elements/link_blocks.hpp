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
      : ElementBlock(BlockKind::link),
        end_i_(end_i),
        end_j_(end_j),
        d_(d),
        compliance_(std::move(compliance)) {}
  Index equation_count() const override { return 12; }
  void write_equations(Index first_row, EquationWriter& out) const override;
  int end_i() const { return end_i_; }
  int end_j() const { return end_j_; }
  const Vec3& d() const { return d_; }
  // C; nothing where the link is rigid.
  const std::optional<Mat6>& compliance() const { return compliance_; }

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
      : ElementBlock(BlockKind::stiffness_link),
        end_i_(end_i),
        end_j_(end_j),
        stiffness_(stiffness) {}
  Index equation_count() const override { return 12; }
  void write_equations(Index first_row, EquationWriter& out) const override;
  const Mat12& stiffness() const { return stiffness_; }

 private:
  int end_i_, end_j_;
  Mat12 stiffness_;
};

}  // namespace stiffmsa::detail
