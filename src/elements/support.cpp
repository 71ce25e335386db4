#include <utility>

#include "elements/connection_blocks.hpp"

namespace stiffmsa::detail {

SupportBlock::SupportBlock(std::vector<int> ends, FreeDirections directions,
                           const std::optional<MatX>& stiffness, std::optional<VecX> preload,
                           std::optional<Vec6> settlement)
    : ends_(std::move(ends)),
      directions_(std::move(directions)),
      preload_(std::move(preload)),
      settlement_(std::move(settlement)) {
  if (stiffness) spring_ = SmallMat(directions_.gram() * SmallMat(*stiffness)) * directions_.free();
}

void SupportBlock::refill(const FreeDirections& directions, const std::optional<MatX>& stiffness,
                          const std::optional<VecX>& preload,
                          const std::optional<Vec6>& settlement) {
  directions_ = directions;
  settlement_ = settlement;
  if (stiffness)
    spring_ = SmallMat(directions_.gram() * SmallMat(*stiffness)) * directions_.free();
  else
    spring_.reset();
  preload_ = preload;
}

void SupportBlock::write_equations(Index row, EquationWriter& out) const {
  const auto& lr = directions_.constrained();
  const auto& lp = directions_.free();
  const Index r = lr.rows(), p = lp.rows();
  const int first = ends_.front();
  for (std::size_t k = 1; k < ends_.size(); ++k) {
    out.add_identity(row, deflection_column(first), 6);
    out.add_identity(row, deflection_column(ends_[k]), 6, -1.0);
    row += 6;
  }
  if (p == 0)
    out.add_identity(row, deflection_column(first), 6);
  else
    out.add_block(row, deflection_column(first), lr);
  row += r;
  if (p == 0) return;
  for (int end : ends_) out.add_block(row, wrench_column(end), lp);
  if (spring_) out.add_block(row, deflection_column(first), *spring_);
}

void SupportBlock::add_external_wrench(Index row, int, const Vec6& wrench, VecX& rhs) const {
  const Index p = directions_.free().rows();
  const Index held = row + 6 * static_cast<Index>(ends_.size()) - p;
  rhs.segment(held, p) += directions_.free() * wrench;
}

// The preload on the free directions' rows; the settlement d on the held ones, Λ_r·Δt_1 = Λ_r·d
// (Δt_1 = d where every direction is held).
void SupportBlock::add_preload(Index row, VecX& rhs) const {
  const Index p = directions_.free().rows();
  if (settlement_) {
    const Index held = row + 6 * (static_cast<Index>(ends_.size()) - 1);
    if (p == 0)
      rhs.segment<6>(held) += *settlement_;
    else
      rhs.segment(held, directions_.constrained().rows()) +=
          directions_.constrained() * *settlement_;
  }
  if (!preload_) return;
  const Index free = row + 6 * static_cast<Index>(ends_.size()) - p;
  rhs.segment(free, p) += directions_.gram() * *preload_;
}

// The ends move as one: Δt = 0 when rigid (plus the settlement d in each load case: it has no
// part along the free directions); when elastic, Λ_r·Δt = 0 and
// G·K·Λ_p·Δt = G·w_0 − Λ_p·R, with R = Σ(W_k − W_ext,k) the reaction; when passive, Δt = Λ_pᵀ·q
// with q its cut unknowns.
void SupportBlock::set_root_deflection(TreeState& state) const {
  MatX deflection = MatX::Zero(6, state.x.cols());
  if (passive()) {
    deflection.noalias() =
        directions_.free().transpose().lazyProduct(state.cut(0, directions_.free().rows()));
  } else if (directions_.free().rows() > 0) {
    const SpringCompliance spring = spring_compliance(directions_, *spring_, preload_);
    MatX reaction = MatX::Zero(6, state.x.cols());
    for (int end : ends_) reaction += state.wrench(end) - state.external.at(end);
    deflection.noalias() = (-spring.compliance).lazyProduct(reaction);
    for (Index c = 0; c < state.external.state_columns(); ++c)
      deflection.col(c) += spring.preload_motion;
  }
  if (settlement_)
    for (Index c = 0; c < state.external.state_columns(); ++c) deflection.col(c) += *settlement_;
  for (int end : ends_) state.set_value(deflection_column(end), deflection);
}

// Σ W_k = Σ W_ext,k + R, the reaction R being the cut unknowns.
void SupportBlock::pass_wrench_to_root(int toward_root, TreeState& state) const {
  state.set_joined_wrench(ends_, toward_root, true);
}

void SupportBlock::pass_deflection_from_root(int toward_root, TreeState& state) const {
  for (int end : ends_)
    if (end != toward_root) state.set_copy(deflection_column(end), deflection_column(toward_root));
}

Index SupportBlock::cut_unknowns(int toward_root) const {
  if (toward_root >= 0) return 6;
  return passive() ? directions_.free().rows() : 0;
}

// Not the root: its last 6 rows (Λ_r·Δt_1 = 0 and the free directions' balance). A passive
// root: its last p rows (Λ_p·Σ W_k = Λ_p·Σ W_ext,k).
void SupportBlock::add_cut_rows(int toward_root, std::vector<Index>& rows) const {
  const Index count = cut_unknowns(toward_root);
  const Index end_rows = 6 * static_cast<Index>(ends_.size());
  for (Index i = end_rows - count; i < end_rows; ++i) rows.push_back(i);
}

}  // namespace stiffmsa::detail
