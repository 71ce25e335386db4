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
  int pattern() const override { return kRigidLinkPattern; }

  // x_i + R_i·d0 − x_j = 0, rotation_vector(R_i·R_jᵀ) = 0 (D·Δt_i − Δt_j = 0 to first order);
  // F_i + F_j = 0, M_i + M_j + (x_j − x_i) × F_j = 0 (W_i + Dᵀ·W_j = 0 at the current d).
  void evaluate(const LoadedInputs& in, Eigen::Ref<VecX> residual, MatX* tangent) const override {
    const EndState& i = in.ends[static_cast<std::size_t>(ends_[0])];
    const EndState& j = in.ends[static_cast<std::size_t>(ends_[1])];
    const Vec3 arm = i.rotation * d0_;
    const RelativeRotation turn = relative_rotation(i.rotation, j.rotation);
    const Vec3 force_j = j.wrench.head<3>();
    const Vec3 chord = j.position - i.position;
    residual.segment<3>(0) = i.position + arm - j.position;
    residual.segment<3>(3) = turn.value;
    residual.segment<3>(6) = i.wrench.head<3>() + force_j;
    residual.segment<3>(9) = i.wrench.tail<3>() + j.wrench.tail<3>() + chord.cross(force_j);
    if (!tangent) return;
    size_tangent(*tangent, 12, 24);
    const Mat3 identity = Mat3::Identity();
    tangent->block<3, 3>(0, position_column(0)) = identity;
    tangent->block<3, 3>(0, position_column(1)) = -identity;
    tangent->block<3, 3>(6, wrench_column(0)) = identity;
    tangent->block<3, 3>(6, wrench_column(1)) = identity;
    tangent->block<3, 3>(9, wrench_column(0) + 3) = identity;
    tangent->block<3, 3>(9, wrench_column(1) + 3) = identity;
    // R_i·d0 turns with δθ_i: −[(R_i·d0)×]·δθ_i.
    tangent->block<3, 3>(0, turn_column(0)) = -skew_of<double>(arm);
    tangent->block<3, 3>(3, turn_column(0)) = turn.of_first;
    tangent->block<3, 3>(3, turn_column(1)) = turn.of_second;
    // Loads along the link add to the balance's δθ_i (loaded_link_loads.cpp).
    tangent->block<3, 3>(9, turn_column(0)).setZero();
    // The moment arm x_j − x_i carries F_j: ∂/∂δx_j = −[F_j×] = −∂/∂δx_i.
    const Mat3 carried = skew_of<double>(force_j);
    tangent->block<3, 3>(9, position_column(0)) = carried;
    tangent->block<3, 3>(9, position_column(1)) = -carried;
    tangent->block<3, 3>(9, wrench_column(1)) = skew_of<double>(chord);
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
