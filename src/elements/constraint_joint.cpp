#include <utility>

#include "elements/connection_blocks.hpp"

namespace stiffmsa::detail {

ConstraintJointBlock::ConstraintJointBlock(std::vector<int> ends, FreeDirections directions,
                                           std::optional<VecX> preload)
    : ends_(std::move(ends)), directions_(std::move(directions)), preload_(std::move(preload)) {}

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

// Σ W_k = Σ W_ext,k, all six components: a rigid joint's equilibrium, and a passive joint's
// with its free components' rows (Λ_p·W_k = Λ_p·W_ext,k) left to the cut, but their sum.
void ConstraintJointBlock::pass_wrench_to_root(int toward_root, TreeState& state) const {
  state.set_joined_wrench(ends_, toward_root, false);
}

// Δt_k = Δt_1 where rigid; a passive joint adds each other end's free motion Λ_pᵀ·q_k, its cut
// unknowns (Λ_r·Λ_pᵀ = 0: the rows of Λ_r are the orthogonal complement of Λ_p's).
void ConstraintJointBlock::pass_deflection_from_root(int toward_root, TreeState& state) const {
  Index motion = 0;
  for (int end : ends_) {
    if (end == toward_root) continue;
    if (p() == 0) {
      state.set_copy(deflection_column(end), deflection_column(toward_root));
      continue;
    }
    state.increment.noalias() = directions_.free().transpose().lazyProduct(state.cut(motion, p()));
    state.set_sum(deflection_column(end), deflection_column(toward_root), 1.0);
    motion += p();
  }
}

Index ConstraintJointBlock::cut_unknowns(int) const {
  return p() * (static_cast<Index>(ends_.size()) - 1);
}

// The free components' rows of the ends beyond the root's: Λ_p·W_k = Λ_p·W_ext,k (+ preload).
void ConstraintJointBlock::add_cut_rows(int toward_root, std::vector<Index>& rows) const {
  const Index m = static_cast<Index>(ends_.size());
  for (Index k = 0; k < m; ++k) {
    if (ends_[static_cast<std::size_t>(k)] == toward_root) continue;
    for (Index i = 0; i < p(); ++i) rows.push_back(r() * m + k * p() + i);
  }
}

}  // namespace stiffmsa::detail
