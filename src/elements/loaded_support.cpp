// Supports and free ends in the loaded mode (docs/theory.md §15.5): the ground does not turn
// with the structure; a settlement moves it by λ times its displacement.
#include <utility>

#include "elements/loaded_derivatives.hpp"

namespace stiffmsa::detail {

namespace {

class LoadedSupportBlock final : public LoadedBlock {
 public:
  LoadedSupportBlock(std::vector<int> ends, const FreeDirections& directions,
                     const std::optional<MatX>& stiffness, const std::optional<VecX>& preload,
                     const std::optional<Vec6>& settlement, const Vec3& unloaded_position)
      : ends_(std::move(ends)),
        directions_(directions),
        settlement_(settlement.value_or(Vec6::Zero())),
        unloaded_position_(unloaded_position) {
    if (stiffness) spring_ = padded_spring(directions_, *stiffness);
    preload_ = held_preload(directions_, preload);
  }
  Index equation_count() const override { return 6 * static_cast<Index>(ends_.size()); }
  const std::vector<int>& ends() const override { return ends_; }
  int pattern() const override { return kSupportPattern + static_cast<int>(directions_.p); }

  // [x_1 − x_k; rotation_vector(R_1·R_kᵀ)] = 0, k = 2..m; Λ_r·g = 0 and, where p > 0,
  // Λ_p·Σ w_k + G·K·Λ_p·g = λ·G·w0, with g = [R_sᵀ·(x_1 − X_1 − λ·s_p); rotation_vector(R_sᵀ·R_1)]
  // the motion from the settled ground (R_s = exp([λ·s_φ×])) and w_k the wrench W_k − W_ext,k
  // about x_1 in the ground's axes.
  void evaluate(const LoadedInputs& in, Eigen::Ref<VecX> residual, MatX* tangent) const override {
    const Index m = static_cast<Index>(ends_.size());
    const Index p = directions_.p, r = 6 - p;
    const Mat3 ground = rotation_matrix(in.load_factor * settlement_.tail<3>());
    const Vec3 ground_position = unloaded_position_ + in.load_factor * settlement_.head<3>();
    // Cleared where derivatives are added: the rows of g and of the wrenches (the last six).
    if (tangent && !size_tangent(*tangent, 6 * m, 12 * m)) tangent->bottomRows<6>().setZero();
    const EndState& first = in.ends[static_cast<std::size_t>(ends_[0])];
    Index row = 0;
    for (Index k = 1; k < m; ++k) {
      const EndState& other = in.ends[static_cast<std::size_t>(ends_[static_cast<std::size_t>(k)])];
      const RelativeRotation turn = relative_rotation(first.rotation, other.rotation);
      residual.segment<3>(row) = first.position - other.position;
      residual.segment<3>(row + 3) = turn.value;
      if (tangent) {
        tangent->block<3, 3>(row, position_column(0)).setIdentity();
        tangent->block<3, 3>(row, position_column(k)) = -Mat3::Identity();
        tangent->block<3, 3>(row + 3, turn_column(0)) = turn.of_first;
        tangent->block<3, 3>(row + 3, turn_column(k)) = turn.of_second;
      }
      row += 6;
    }
    // g and its derivative in [δx_1; δθ_1].
    const Mat3 back = ground.transpose();
    Vec6 g;
    g.head<3>() = back * (first.position - ground_position);
    g.tail<3>() = rotation_vector<double>(Mat3(back * first.rotation));
    Mat6 motion = Mat6::Zero();
    motion.topLeftCorner<3, 3>() = back;
    motion.bottomRightCorner<3, 3>() = inverse_left_jacobian<double>(Vec3(g.tail<3>())) * back;
    const SixRows held_rows{directions_.rows, p, r};
    set_rows(residual, row, held_rows, g);
    if (tangent) add_derivative(*tangent, row, position_column(0), held_rows, motion);
    row += r;
    if (p == 0) return;
    add_wrench_sum(in, ends_, ground, false, SixRows{directions_.rows, 0, p}, row, residual,
                   tangent);
    if (spring_) {
      const SixRows spring{*spring_, 0, p};
      set_rows(residual, row, spring, g, true);
      if (tangent) add_derivative(*tangent, row, position_column(0), spring, motion);
    }
    if (preload_) residual.segment(row, p) -= in.load_factor * *preload_;
  }

 private:
  std::vector<int> ends_;
  FreeDirections directions_;
  std::optional<Mat6> spring_;  // G·K·Λ_p, padded with zero rows
  std::optional<SmallVec> preload_;
  Vec6 settlement_;
  Vec3 unloaded_position_;
};

class LoadedFreeEndBlock final : public LoadedBlock {
 public:
  explicit LoadedFreeEndBlock(int end) : ends_{end} {}
  Index equation_count() const override { return 6; }
  const std::vector<int>& ends() const override { return ends_; }
  int pattern() const override { return kFreeEndPattern; }
  void evaluate(const LoadedInputs& in, Eigen::Ref<VecX> residual, MatX* tangent) const override {
    const EndState& s = in.ends[static_cast<std::size_t>(ends_[0])];
    residual = s.wrench - in.external[static_cast<std::size_t>(ends_[0])];
    if (!tangent) return;
    size_tangent(*tangent, 6, 12);
    tangent->block<6, 6>(0, 6).setIdentity();
  }

 private:
  std::vector<int> ends_;
};

}  // namespace

std::unique_ptr<LoadedBlock> make_loaded_support(std::vector<int> ends,
                                                 const FreeDirections& directions,
                                                 const std::optional<MatX>& stiffness,
                                                 const std::optional<VecX>& preload,
                                                 const std::optional<Vec6>& settlement,
                                                 const Vec3& unloaded_position) {
  return std::make_unique<LoadedSupportBlock>(std::move(ends), directions, stiffness, preload,
                                              settlement, unloaded_position);
}

std::unique_ptr<LoadedBlock> make_loaded_free_end(int end) {
  return std::make_unique<LoadedFreeEndBlock>(end);
}

}  // namespace stiffmsa::detail
