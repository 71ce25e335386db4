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
    if (stiffness)
      spring_ = SmallMat(directions_.gram() * SmallMat(*stiffness)) * directions_.free();
    if (preload) preload_ = SmallVec(directions_.gram() * *preload);
  }
  Index equation_count() const override { return 6 * static_cast<Index>(ends_.size()); }
  const std::vector<int>& ends() const override { return ends_; }

  // [x_1 − x_k; rotation_vector(R_1·R_kᵀ)] = 0, k = 2..m; Λ_r·g = 0 and, where p > 0,
  // Λ_p·Σ w_k + G·K·Λ_p·g = λ·G·w0, with g = [R_sᵀ·(x_1 − X_1 − λ·s_p); rotation_vector(R_sᵀ·R_1)]
  // the motion from the settled ground (R_s = exp([λ·s_φ×])) and w_k the wrench W_k − W_ext,k
  // about x_1 in the ground's axes.
  void evaluate(const LoadedInputs& in, Eigen::Ref<VecX> residual, MatX* tangent) const override {
    const Index m = static_cast<Index>(ends_.size());
    const Index p = directions_.p, r = 6 - p;
    const Mat3 ground = rotation_matrix(in.load_factor * settlement_.tail<3>());
    const Vec3 ground_position = unloaded_position_ + in.load_factor * settlement_.head<3>();
    evaluate_block(
        in, ends_, 6 * m,
        [&](const auto& e, auto& out) {
          using T = typename std::decay_t<decltype(out)>::Scalar;
          Index row = 0;
          for (Index k = 1; k < m; ++k) {
            const auto& other = e[static_cast<std::size_t>(k)];
            out.template segment<3>(row) = e[0].x - other.x;
            out.template segment<3>(row + 3) =
                rotation_vector<T>(Mat3T<T>(e[0].rotation * other.rotation.transpose()));
            row += 6;
          }
          const Mat3T<T> turn = ground.cast<T>();
          Vec6T<T> g;
          g.template head<3>() = turn.transpose() * (e[0].x - ground_position.cast<T>());
          g.template tail<3>() = rotation_vector<T>(Mat3T<T>(turn.transpose() * e[0].rotation));
          const Eigen::Matrix<T, 6, 6> rows = directions_.rows.cast<T>();
          out.segment(row, r) = rows.bottomRows(r) * g;
          row += r;
          if (p == 0) return;
          Vec6T<T> sum = Vec6T<T>::Zero();
          for (Index k = 0; k < m; ++k) {
            const auto& end = e[static_cast<std::size_t>(k)];
            const Vec6T<T> applied =
                end.wrench -
                external_of<T>(
                    in.external[static_cast<std::size_t>(ends_[static_cast<std::size_t>(k)])]);
            sum += wrench_in_axes<T>(applied, end.x, e[0].x, turn);
          }
          out.segment(row, p) = rows.topRows(p) * sum;
          if (spring_) {
            const Eigen::Matrix<T, Eigen::Dynamic, 6> spring = spring_->cast<T>();
            out.segment(row, p) += spring * g;
          }
          if (preload_)
            for (Index c = 0; c < p; ++c) out(row + c) -= T(in.load_factor * (*preload_)(c));
        },
        residual, tangent);
  }

 private:
  std::vector<int> ends_;
  FreeDirections directions_;
  std::optional<SmallMat> spring_;
  std::optional<SmallVec> preload_;
  Vec6 settlement_;
  Vec3 unloaded_position_;
};

class LoadedFreeEndBlock final : public LoadedBlock {
 public:
  explicit LoadedFreeEndBlock(int end) : ends_{end} {}
  Index equation_count() const override { return 6; }
  const std::vector<int>& ends() const override { return ends_; }
  void evaluate(const LoadedInputs& in, Eigen::Ref<VecX> residual, MatX* tangent) const override {
    const EndState& s = in.ends[static_cast<std::size_t>(ends_[0])];
    residual = s.wrench - in.external[static_cast<std::size_t>(ends_[0])];
    if (!tangent) return;
    tangent->setZero(6, 12);
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
