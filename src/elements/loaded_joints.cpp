// Joints in the loaded mode (docs/theory.md §15.4): their free and constrained directions turn
// with their first link end; relative motions are finite (a revolute joint's angle), wrenches
// are taken about the first end's current point.
#include <utility>

#include "elements/loaded_derivatives.hpp"

namespace stiffmsa::detail {

namespace {

// The finite motion of end k relative to end 1 in end 1's turned axes:
// [R_1ᵀ·(x_k − x_1); rotation_vector(R_1ᵀ·R_k)].
template <class T>
Vec6T<T> relative_motion(const EndT<T>& first, const EndT<T>& other) {
  Vec6T<T> q;
  q.template head<3>() = first.rotation.transpose() * (other.x - first.x);
  q.template tail<3>() = rotation_vector<T>(Mat3T<T>(first.rotation.transpose() * other.rotation));
  return q;
}

class LoadedConstraintJointBlock final : public LoadedBlock {
 public:
  LoadedConstraintJointBlock(std::vector<int> ends, const FreeDirections& directions,
                             const std::optional<VecX>& preload)
      : ends_(std::move(ends)), directions_(directions) {
    if (preload) preload_ = SmallVec(directions_.gram() * *preload);
  }
  Index equation_count() const override { return 6 * static_cast<Index>(ends_.size()); }
  const std::vector<int>& ends() const override { return ends_; }

  // Λ_r·(−q_k) = 0, k = 2..m; Λ_r·Σ w_k = 0; Λ_p·w_k = ±λ·G·w0 (ends 1, 2), with w_k the
  // wrench W_k − W_ext,k about x_1 in end 1's axes.
  void evaluate(const LoadedInputs& in, Eigen::Ref<VecX> residual, MatX* tangent) const override {
    const Index m = static_cast<Index>(ends_.size());
    const Index p = directions_.p, r = 6 - p;
    evaluate_block(
        in, ends_, 6 * m,
        [&](const auto& e, auto& out) {
          using T = typename std::decay_t<decltype(out)>::Scalar;
          const Eigen::Matrix<T, 6, 6> rows = directions_.rows.cast<T>();
          Index row = 0;
          for (Index k = 1; k < m; ++k) {
            const Vec6T<T> q = relative_motion(e[0], e[static_cast<std::size_t>(k)]);
            out.segment(row, r) = -(rows.bottomRows(r) * q);
            row += r;
          }
          std::vector<Vec6T<T>> held(static_cast<std::size_t>(m));
          Vec6T<T> sum = Vec6T<T>::Zero();
          for (Index k = 0; k < m; ++k) {
            const auto& end = e[static_cast<std::size_t>(k)];
            const Vec6T<T> applied =
                end.wrench -
                external_of<T>(
                    in.external[static_cast<std::size_t>(ends_[static_cast<std::size_t>(k)])]);
            held[static_cast<std::size_t>(k)] =
                wrench_in_axes<T>(applied, end.x, e[0].x, e[0].rotation);
            sum += held[static_cast<std::size_t>(k)];
          }
          out.segment(row, r) = rows.bottomRows(r) * sum;
          row += r;
          for (Index k = 0; k < m; ++k) {
            out.segment(row, p) = rows.topRows(p) * held[static_cast<std::size_t>(k)];
            if (preload_ && k < 2) {
              const double sign = k == 0 ? -in.load_factor : in.load_factor;
              for (Index c = 0; c < p; ++c) out(row + c) += T(sign * (*preload_)(c));
            }
            row += p;
          }
        },
        residual, tangent);
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
        spring_(SmallMat(directions_.gram() * SmallMat(stiffness)) * directions_.free()) {
    if (preload) preload_ = SmallVec(directions_.gram() * *preload);
  }
  Index equation_count() const override { return 12; }
  const std::vector<int>& ends() const override { return ends_; }

  // w_1 + w_2 = 0 (both about x_1, global axes); Λ_r·(−q_2) = 0;
  // Λ_p·w_1 − G·K·Λ_p·q_2 = λ·G·w0, w_1 in end 1's axes: the spring on the finite motion q_2.
  void evaluate(const LoadedInputs& in, Eigen::Ref<VecX> residual, MatX* tangent) const override {
    const Index p = directions_.p, r = 6 - p;
    evaluate_block(
        in, ends_, 12,
        [&](const auto& e, auto& out) {
          using T = typename std::decay_t<decltype(out)>::Scalar;
          const Vec6T<T> applied_1 =
              e[0].wrench - external_of<T>(in.external[static_cast<std::size_t>(ends_[0])]);
          const Vec6T<T> applied_2 =
              e[1].wrench - external_of<T>(in.external[static_cast<std::size_t>(ends_[1])]);
          const Mat3T<T> global = Mat3T<T>::Identity();
          out.template segment<6>(0) =
              applied_1 + wrench_in_axes<T>(applied_2, e[1].x, e[0].x, global);
          const Vec6T<T> q = relative_motion(e[0], e[1]);
          const Eigen::Matrix<T, 6, 6> rows = directions_.rows.cast<T>();
          out.segment(6, r) = -(rows.bottomRows(r) * q);
          const Vec6T<T> held_1 = wrench_in_axes<T>(applied_1, e[0].x, e[0].x, e[0].rotation);
          const Eigen::Matrix<T, Eigen::Dynamic, 6> spring = spring_.cast<T>();
          out.segment(6 + r, p) = rows.topRows(p) * held_1 - spring * q;
          if (preload_)
            for (Index c = 0; c < p; ++c) out(6 + r + c) -= T(in.load_factor * (*preload_)(c));
        },
        residual, tangent);
  }

 private:
  std::vector<int> ends_;
  FreeDirections directions_;
  SmallMat spring_;  // G·K·Λ_p
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
