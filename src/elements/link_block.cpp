#include "elements/link_blocks.hpp"

#include "elements/cad_link.hpp"

namespace stiffmsa::detail {

void LinkBlock::write_equations(Index row, EquationWriter& out) const {
  // Only the [d×]ᵀ block of D is off the identity; it is written whole, zeros included.
  const Mat3 coupling = skew(d_).transpose();
  // Compatibility: Δp_i + [d×]ᵀΔφ_i − Δp_j (+ C·W_j) = 0, Δφ_i − Δφ_j (+ C·W_j) = 0.
  out.add_identity(row, deflection_column(end_i_), 6);
  out.add_block(row, deflection_column(end_i_) + 3, coupling);
  out.add_identity(row, deflection_column(end_j_), 6, -1.0);
  if (compliance_) out.add_block(row, wrench_column(end_j_), *compliance_);
  // Equilibrium: W_i + Dᵀ W_j = 0, Dᵀ = [[I, 0], [[d×], I]].
  out.add_identity(row + 6, wrench_column(end_i_), 6);
  out.add_identity(row + 6, wrench_column(end_j_), 6);
  out.add_block(row + 9, wrench_column(end_j_), coupling.transpose());
}

std::optional<Mat12> LinkBlock::end_stiffness() const {
  if (!compliance_) return std::nullopt;
  return free_free_stiffness(*compliance_, d_);
}

// W_i + Dᵀ·W_j = 0 solved for the end toward the root: W_i = −W_j − [0; d×F_j], or
// W_j = −W_i + [0; d×F_i].
void LinkBlock::pass_wrench_to_root(int toward_root, TreeState& state) const {
  const int far = toward_root == end_i_ ? end_j_ : end_i_;
  const double sign = toward_root == end_i_ ? -1.0 : 1.0;
  RowMajorMatX& increment = state.increment;
  increment.topRows<3>().setZero();
  const Mat3 moment_arm = sign * skew(d_);
  increment.bottomRows<3>().noalias() = moment_arm.lazyProduct(state.wrench(far).topRows<3>());
  state.set_sum(wrench_column(toward_root), wrench_column(far), -1.0);
}

// D·Δt_i − Δt_j + C·W_j = 0 solved for the end away from the root, with D·Δt = Δt + [−d×Δφ; 0]:
// Δt_j = Δt_i + [−d×Δφ_i; 0] + C·W_j, or Δt_i = Δt_j − C·W_j + [d×Δφ_i; 0], Δφ_i = Δφ_j −
// (C·W_j)_φ.
void LinkBlock::pass_deflection_from_root(int toward_root, TreeState& state) const {
  const Mat3 d_cross = skew(d_);
  RowMajorMatX& increment = state.increment;
  if (compliance_)
    increment.noalias() = compliance_->lazyProduct(state.wrench(end_j_));
  else
    increment.setZero();
  if (toward_root == end_i_) {
    increment.topRows<3>().noalias() -=
        d_cross.lazyProduct(state.deflection(end_i_).bottomRows<3>());
    state.set_sum(deflection_column(end_j_), deflection_column(end_i_), 1.0);
  } else {
    increment = -increment;
    increment.topRows<3>().noalias() +=
        d_cross.lazyProduct(state.deflection(end_j_).bottomRows<3>());
    increment.topRows<3>().noalias() += d_cross.lazyProduct(increment.bottomRows<3>());
    state.set_sum(deflection_column(end_i_), deflection_column(end_j_), 1.0);
  }
}

}  // namespace stiffmsa::detail
