#include <utility>

#include "elements/connection_blocks.hpp"

namespace stiffmsa::detail {

ElasticJointBlock::ElasticJointBlock(int end_1, int end_2, FreeDirections directions,
                                     const MatX& stiffness, std::optional<VecX> preload)
    : ElementBlock(BlockKind::elastic_joint),
      end_1_(end_1),
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

}  // namespace stiffmsa::detail
