#include "elements/link_blocks.hpp"

namespace stiffmsa::detail {

void StiffnessLinkBlock::write_equations(Index row, EquationWriter& out) const {
  out.add_identity(row, wrench_column(end_i_), 6);
  out.add_identity(row + 6, wrench_column(end_j_), 6);
  out.add_block(row, deflection_column(end_i_), stiffness_.leftCols<6>(), -1.0);
  out.add_block(row, deflection_column(end_j_), stiffness_.rightCols<6>(), -1.0);
}

}  // namespace stiffmsa::detail
