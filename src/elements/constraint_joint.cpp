#include <utility>

#include "elements/connection_blocks.hpp"

namespace stiffmsa::detail {

ConstraintJointBlock::ConstraintJointBlock(std::vector<int> ends, FreeDirections directions,
                                           std::optional<VecX> preload)
    : ends_(std::move(ends)), directions_(std::move(directions)), preload_(std::move(preload)) {}

void ConstraintJointBlock::write_equations(Index row, EquationWriter& out) const {
  const auto& lr = directions_.constrained();
  const auto& lp = directions_.free();
  const bool rigid = p() == 0;  // Λ_r = I: only the diagonal is structurally nonzero
  auto write_constrained = [&](Index at, Index column, double sign) {
    if (rigid)
      out.add_identity(at, column, 6, sign);
    else
      out.add_block(at, column, sign * lr);
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

// Σ W_k = Σ W_ext,k (Λ_r = I) solved for the end toward the root, as a running sum through
// the first of the other ends.
void ConstraintJointBlock::pass_wrench_to_root(int toward_root, TreeState& state) const {
  int through = -1;
  RowMajorMatX& increment = state.increment;
  increment.setZero();
  for (int end : ends_) {
    increment += state.external.at(end);
    if (end == toward_root) continue;
    if (through < 0)
      through = end;
    else
      increment -= state.wrench(end) + state.x_low.middleRows<6>(wrench_column(end));
  }
  if (through < 0)  // a joint of one end (validation refuses those): the loads alone
    state.set_value(wrench_column(toward_root), increment);
  else
    state.set_sum(wrench_column(toward_root), wrench_column(through), -1.0);
}

// Δt_1 = Δt_k (Λ_r = I).
void ConstraintJointBlock::pass_deflection_from_root(int toward_root, TreeState& state) const {
  for (int end : ends_)
    if (end != toward_root) state.set_copy(deflection_column(end), deflection_column(toward_root));
}

}  // namespace stiffmsa::detail
