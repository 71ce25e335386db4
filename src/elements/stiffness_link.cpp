#include "elements/link_blocks.hpp"

namespace stiffmsa::detail {

void StiffnessLinkBlock::write_equations(Index row, EquationWriter& out) const {
  out.add_identity(row, wrench_column(end_i_), 6);
  out.add_identity(row + 6, wrench_column(end_j_), 6);
  const Mat12 minus_k = -stiffness_;
  out.add_block(row, deflection_column(end_i_), minus_k.leftCols<6>());
  out.add_block(row, deflection_column(end_j_), minus_k.rightCols<6>());
}

}  // namespace stiffmsa::detail
