#include <utility>

#include "elements/connection_blocks.hpp"

namespace stiffmsa::detail {

ElasticJointBlock::ElasticJointBlock(int end_1, int end_2, FreeDirections directions,
                                     const MatX& stiffness, std::optional<VecX> preload)
    : end_1_(end_1),
      end_2_(end_2),
      directions_(std::move(directions)),
      // The spring resists q = Λ_p·(Δt_2 − Δt_1): it pulls end 1 along +q.
      spring_(SmallMat(directions_.gram() * SmallMat(stiffness)) * directions_.free()),
      preload_(std::move(preload)) {}

void ElasticJointBlock::refill(const FreeDirections& directions, const MatX& stiffness,
                               const std::optional<VecX>& preload) {
  directions_ = directions;
  spring_ = SmallMat(directions_.gram() * SmallMat(stiffness)) * directions_.free();
  preload_ = preload;
}

void ElasticJointBlock::write_equations(Index row, EquationWriter& out) const {
  const auto& lr = directions_.constrained();
  const auto& lp = directions_.free();
  out.add_identity(row, wrench_column(end_1_), 6);
  out.add_identity(row, wrench_column(end_2_), 6);
  row += 6;
  out.add_block(row, deflection_column(end_1_), lr);
  out.add_block(row, deflection_column(end_2_), lr, -1.0);
  row += lr.rows();
  out.add_block(row, wrench_column(end_1_), lp);
  out.add_block(row, deflection_column(end_1_), spring_);
  out.add_block(row, deflection_column(end_2_), spring_, -1.0);
}

void ElasticJointBlock::add_external_wrench(Index row, int end_id, const Vec6& wrench,
                                            VecX& rhs) const {
  rhs.segment<6>(row) += wrench;
  if (end_id == end_1_) {
    const Index spring_row = row + 6 + directions_.constrained().rows();
    rhs.segment(spring_row, directions_.free().rows()) += directions_.free() * wrench;
  }
}

void ElasticJointBlock::add_preload(Index row, VecX& rhs) const {
  if (!preload_) return;
  const Index spring_row = row + 6 + directions_.constrained().rows();
  rhs.segment(spring_row, directions_.free().rows()) += directions_.gram() * *preload_;
}

// W_1 + W_2 = W_ext,1 + W_ext,2 solved for the end toward the root.
void ElasticJointBlock::pass_wrench_to_root(int toward_root, TreeState& state) const {
  const int other = toward_root == end_1_ ? end_2_ : end_1_;
  state.increment = state.external.at(end_1_) + state.external.at(end_2_);
  state.set_sum(wrench_column(toward_root), wrench_column(other), -1.0);
}

// The relative deflection δ = Δt_2 − Δt_1 from Λ_r·δ = 0 and G·K·Λ_p·δ = Λ_p·(W_1 − W_ext,1) −
// G·w_0.
void ElasticJointBlock::pass_deflection_from_root(int toward_root, TreeState& state) const {
  const SpringCompliance spring = spring_compliance(directions_, spring_, preload_);
  // δ is added to end 1's deflection, or taken from end 2's.
  const double sign = toward_root == end_1_ ? 1.0 : -1.0;
  const Mat6 compliance = sign * spring.compliance;
  RowMajorMatX& delta = state.increment;
  delta.noalias() = compliance.lazyProduct(state.wrench(end_1_));
  if (state.external.any_at(end_1_))
    delta.noalias() -= compliance.lazyProduct(state.external.at(end_1_));
  for (Index c = 0; c < state.external.state_columns(); ++c)
    delta.col(c) -= sign * spring.preload_motion;
  if (toward_root == end_1_)
    state.set_sum(deflection_column(end_2_), deflection_column(end_1_), 1.0);
  else
    state.set_sum(deflection_column(end_1_), deflection_column(end_2_), 1.0);
}

}  // namespace stiffmsa::detail
