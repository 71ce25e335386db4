#include <utility>

#include "elements/connection_blocks.hpp"

namespace stiffmsa::detail {

ConstraintJointBlock::ConstraintJointBlock(std::vector<int> ends, FreeDirections directions,
                                           std::optional<VecX> preload)
    : ElementBlock(BlockKind::constraint_joint),
      ends_(std::move(ends)),
      directions_(std::move(directions)),
      preload_(std::move(preload)) {}

void ConstraintJointBlock::refill(const FreeDirections& directions,
                                  const std::optional<VecX>& preload) {
  directions_ = directions;
  preload_ = preload;
}

void ConstraintJointBlock::write_equations(Index row, EquationWriter& out) const {
  const auto& lr = directions_.constrained();
  const auto& lp = directions_.free();
  const bool rigid = p() == 0;  // Λ_r = I: only the diagonal is structurally nonzero
  auto write_constrained = [&](Index at, Index column, double sign) {
    if (rigid)
      out.add_identity(at, column, 6, sign);
    else
      out.add_block(at, column, lr, sign);
  };
  for (std::size_t k = 1; k < ends_.size(); ++k) {
    write_constrained(row, deflection_column(ends_[0]), 1.0);
    write_constrained(row, deflection_column(ends_[k]), -1.0);
    row += r();
  }
  for (int end : ends_) write_constrained(row, wrench_column(end), 1.0);
  row += r();
  for (int end : ends_) {
    out.add_block(row, wrench_column(end), lp);
    row += p();
  }
}

void ConstraintJointBlock::add_external_wrench(Index row, int end_id, const Vec6& wrench,
                                               VecX& rhs) const {
  const Index m = static_cast<Index>(ends_.size());
  const Index equilibrium = row + r() * (m - 1);
  rhs.segment(equilibrium, r()) += directions_.constrained() * wrench;
  for (Index k = 0; k < m; ++k)
    if (ends_[static_cast<std::size_t>(k)] == end_id)
      rhs.segment(equilibrium + r() + k * p(), p()) += directions_.free() * wrench;
}

void ConstraintJointBlock::add_preload(Index row, VecX& rhs) const {
  if (!preload_) return;
  const Index passive = row + r() * static_cast<Index>(ends_.size());
  const SmallVec projected = directions_.gram() * *preload_;
  rhs.segment(passive, p()) += projected;
  rhs.segment(passive + p(), p()) -= projected;
}

}  // namespace stiffmsa::detail
