#include "elements/link_blocks.hpp"

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

}  // namespace stiffmsa::detail
