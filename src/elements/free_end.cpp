#include "elements/connection_blocks.hpp"

namespace stiffmsa::detail {

void FreeEndBlock::write_equations(Index row, EquationWriter& out) const {
  out.add_identity(row, wrench_column(end_), 6);
}

void FreeEndBlock::add_external_wrench(Index row, int, const Vec6& wrench, VecX& rhs) const {
  rhs.segment<6>(row) += wrench;
}

}  // namespace stiffmsa::detail
