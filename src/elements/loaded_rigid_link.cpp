// A rigid link in the loaded mode (docs/theory.md §15.3): it moves as a rigid body and balances
// the wrenches at its ends about its current from end.
#include "elements/loaded_derivatives.hpp"

namespace stiffmsa::detail {

namespace {

class LoadedRigidLinkBlock final : public LoadedBlock {
 public:
  LoadedRigidLinkBlock(int end_i, int end_j, const Vec3& d0) : ends_{end_i, end_j}, d0_(d0) {}
  Index equation_count() const override { return 12; }
  const std::vector<int>& ends() const override { return ends_; }

  // x_i + R_i·d0 − x_j = 0, rotation_vector(R_i·R_jᵀ) = 0 (D·Δt_i − Δt_j = 0 to first order);
  // F_i + F_j = 0, M_i + M_j + (x_j − x_i) × F_j = 0 (W_i + Dᵀ·W_j = 0 at the current d).
  void evaluate(const LoadedInputs& in, Eigen::Ref<VecX> residual, MatX* tangent) const override {
    evaluate_block(
        in, ends_, 12,
        [&](const auto& e, auto& r) {
          using T = typename std::decay_t<decltype(r)>::Scalar;
          const auto& i = e[0];
          const auto& j = e[1];
          r.template segment<3>(0) = i.x + i.rotation * d0_.cast<T>() - j.x;
          r.template segment<3>(3) =
              rotation_vector<T>(Mat3T<T>(i.rotation * j.rotation.transpose()));
          const Vec3T<T> force_j = j.wrench.template head<3>();
          r.template segment<3>(6) = i.wrench.template head<3>() + force_j;
          r.template segment<3>(9) = i.wrench.template tail<3>() + j.wrench.template tail<3>() +
                                     (j.x - i.x).cross(force_j);
        },
        residual, tangent);
  }

 private:
  std::vector<int> ends_;
  Vec3 d0_;
};

}  // namespace

std::unique_ptr<LoadedBlock> make_loaded_rigid_link(int end_i, int end_j, const Vec3& d0) {
  return std::make_unique<LoadedRigidLinkBlock>(end_i, end_j, d0);
}

}  // namespace stiffmsa::detail
