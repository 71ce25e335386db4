#include <utility>

#include "elements/connection_blocks.hpp"

namespace stiffmsa::detail {

SupportBlock::SupportBlock(std::vector<int> ends, FreeDirections directions,
                           const std::optional<MatX>& stiffness, std::optional<VecX> preload,
                           std::optional<Vec6> settlement)
    : ElementBlock(BlockKind::support),
      ends_(std::move(ends)),
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

}  // namespace stiffmsa::detail
