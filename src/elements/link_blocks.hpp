#pragma once
// Link element blocks: 12 equations per link over its two link ends i (from) and j (to).
#include "elements/element_block.hpp"

namespace stiffmsa::detail {

// Paper eq. (1): [W_i; W_j] − K·[Δt_i; Δt_j] = 0, K the global free-free stiffness.
class FlexibleLinkBlock final : public ElementBlock {
 public:
  FlexibleLinkBlock(int end_i, int end_j, const Mat12& stiffness)
      : end_i_(end_i), end_j_(end_j), stiffness_(stiffness) {}
  Index equation_count() const override { return 12; }
  void write_equations(Index first_row, EquationWriter& out) const override;

 private:
  int end_i_, end_j_;
  Mat12 stiffness_;
};

// Paper eqs. (2), (3): D·Δt_i − Δt_j = 0 and W_i + Dᵀ·W_j = 0, d = p_j − p_i.
class RigidLinkBlock final : public ElementBlock {
 public:
  RigidLinkBlock(int end_i, int end_j, const Vec3& d) : end_i_(end_i), end_j_(end_j), d_(d) {}
  Index equation_count() const override { return 12; }
  void write_equations(Index first_row, EquationWriter& out) const override;

 private:
  int end_i_, end_j_;
  Vec3 d_;
};

}  // namespace stiffmsa::detail
