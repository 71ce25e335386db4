// Joints in the loaded mode (docs/theory.md §15.4): their free and constrained directions turn
// with their first link end; relative motions are finite (a revolute joint's angle), wrenches
// are taken about the first end's current point.
#include <utility>

#include "elements/loaded_derivatives.hpp"

namespace stiffmsa::detail {

namespace {

class LoadedConstraintJointBlock final : public LoadedBlock {
 public:
  LoadedConstraintJointBlock(std::vector<int> ends, const FreeDirections& directions,
                             const std::optional<VecX>& preload)
      : ends_(std::move(ends)), directions_(directions) {
    preload_ = held_preload(directions_, preload);
  }
  Index equation_count() const override { return 6 * static_cast<Index>(ends_.size()); }
  const std::vector<int>& ends() const override { return ends_; }
  int pattern() const override { return kConstraintJointPattern + static_cast<int>(directions_.p); }

  // Λ_r·(−q_k) = 0, k = 2..m; Λ_r·Σ w_k = 0; Λ_p·w_k = ±λ·G·w0 (ends 1, 2), with w_k the
  // wrench W_k − W_ext,k about x_1 in end 1's axes.
  void evaluate(const LoadedInputs& in, Eigen::Ref<VecX> residual, MatX* tangent) const override {
    const Index m = static_cast<Index>(ends_.size());
    const Index p = directions_.p, r = 6 - p;
    const SixRows held_rows{directions_.rows, p, r}, free_rows{directions_.rows, 0, p};
    const SixRows minus_held{directions_.rows, p, r, -1};
    if (tangent && !size_tangent(*tangent, 6 * m, 12 * m)) {
      // Cleared where the derivatives below are added: end 1's and end k's [δx, δθ] in the rows
      // of q_k, every column in the wrenches' rows.
      for (Index k = 1; k < m; ++k) {
        tangent->block((k - 1) * r, position_column(0), r, 6).setZero();
        tangent->block((k - 1) * r, position_column(k), r, 6).setZero();
      }
      tangent->bottomRows(r + m * p).setZero();
    }
    const EndState& first = in.ends[static_cast<std::size_t>(ends_[0])];
    Index row = 0;
    for (Index k = 1; k < m; ++k) {
      const RelativeMotion q = relative_motion(
          first, in.ends[static_cast<std::size_t>(ends_[static_cast<std::size_t>(k)])]);
      set_rows(residual, row, minus_held, q.value);
      if (tangent) {
        add_derivative(*tangent, row, position_column(0), minus_held, q.of_first);
        add_derivative(*tangent, row, position_column(k), minus_held, q.of_other);
      }
      row += r;
    }
    // Each w_k enters the sum's Λ_r rows and its own Λ_p rows: one product Λ·∂w_k serves both.
    const Index sum_row = row;
    row += r;
    Vec6 sum = Vec6::Zero();
    for (Index k = 0; k < m; ++k) {
      const auto e = static_cast<std::size_t>(ends_[static_cast<std::size_t>(k)]);
      const HeldWrench w = held_wrench(in.ends[e], in.external[e], first.position, first.rotation);
      sum += w.value;
      set_rows(residual, row, free_rows, w.value);
      if (preload_ && k < 2) {
        const double sign = k == 0 ? -in.load_factor : in.load_factor;
        residual.segment(row, p) += sign * *preload_;
      }
      if (tangent) add_held_wrench_split(*tangent, sum_row, row, directions_.rows, p, w, k);
      row += p;
    }
    set_rows(residual, sum_row, held_rows, sum);
  }

 private:
  std::vector<int> ends_;
  FreeDirections directions_;
  std::optional<SmallVec> preload_;  // G·w0
};

class LoadedElasticJointBlock final : public LoadedBlock {
 public:
  LoadedElasticJointBlock(int end_1, int end_2, const FreeDirections& directions,
                          const MatX& stiffness, const std::optional<VecX>& preload)
      : ends_{end_1, end_2},
        directions_(directions),
        spring_(padded_spring(directions_, stiffness)) {
    const Index p = directions_.p, r = 6 - p;
    motion_rows_.topRows(r) = -directions_.constrained();
    motion_rows_.bottomRows(p) = -spring_.topRows(p);
    preload_ = held_preload(directions_, preload);
  }
  Index equation_count() const override { return 12; }
  const std::vector<int>& ends() const override { return ends_; }
  int pattern() const override { return kElasticJointPattern + static_cast<int>(directions_.p); }

  // w_1 + w_2 = 0 (both about x_1, global axes); Λ_r·(−q_2) = 0;
  // Λ_p·w_1 − G·K·Λ_p·q_2 = λ·G·w0, w_1 in end 1's axes: the spring on the finite motion q_2.
  void evaluate(const LoadedInputs& in, Eigen::Ref<VecX> residual, MatX* tangent) const override {
    const Index p = directions_.p, r = 6 - p;
    const SixRows free_rows{directions_.rows, 0, p};
    if (tangent && !size_tangent(*tangent, 12, 24)) {
      // Cleared where the derivatives below are added: the balance's rows, and end 1's δW in
      // the spring's.
      tangent->topRows<6>().setZero();
      tangent->block<6, 6>(6, wrench_column(0)).setZero();
    }
    const EndState& first = in.ends[static_cast<std::size_t>(ends_[0])];
    const EndState& second = in.ends[static_cast<std::size_t>(ends_[1])];
    add_wrench_sum(in, ends_, Mat3::Identity(), false, SixRows{kSixIdentity}, 0, residual, tangent);
    const RelativeMotion q = relative_motion(first, second);
    residual.segment<6>(6) = motion_rows_ * q.value;
    const HeldWrench w = held_wrench(first, in.external[static_cast<std::size_t>(ends_[0])],
                                     first.position, first.rotation);
    set_rows(residual, 6 + r, free_rows, w.value, true);
    if (preload_) residual.segment(6 + r, p) -= in.load_factor * *preload_;
    if (!tangent) return;
    // q's derivatives have zero blocks (relative_motion): the products over the others alone,
    // the terms added in the same order.
    const auto by_position = motion_rows_.leftCols<3>(), by_turn = motion_rows_.rightCols<3>();
    tangent->block<6, 3>(6, position_column(0)) = by_position * q.of_first.topLeftCorner<3, 3>();
    tangent->block<6, 3>(6, turn_column(0)) = motion_rows_ * q.of_first.rightCols<3>();
    tangent->block<6, 3>(6, position_column(1)) = by_position * q.of_other.topLeftCorner<3, 3>();
    tangent->block<6, 3>(6, turn_column(1)) = by_turn * q.of_other.bottomRightCorner<3, 3>();
    add_held_wrench(*tangent, 6 + r, free_rows, w, 0, true);
  }

 private:
  std::vector<int> ends_;
  FreeDirections directions_;
  Mat6 spring_;       // G·K·Λ_p, padded with zero rows
  Mat6 motion_rows_;  // [−Λ_r; −G·K·Λ_p]: the rows 7…12 of q_2
  std::optional<SmallVec> preload_;
};

}  // namespace

std::unique_ptr<LoadedBlock> make_loaded_constraint_joint(std::vector<int> ends,
                                                          const FreeDirections& directions,
                                                          const std::optional<VecX>& preload) {
  return std::make_unique<LoadedConstraintJointBlock>(std::move(ends), directions, preload);
}

std::unique_ptr<LoadedBlock> make_loaded_elastic_joint(int end_1, int end_2,
                                                       const FreeDirections& directions,
                                                       const MatX& stiffness,
                                                       const std::optional<VecX>& preload) {
  return std::make_unique<LoadedElasticJointBlock>(end_1, end_2, directions, stiffness, preload);
}

}  // namespace stiffmsa::detail
