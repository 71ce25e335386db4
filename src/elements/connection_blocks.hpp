#pragma once
// Connection blocks hold link ends: joints, supports and free ends. Together with the link
// blocks they give exactly 12 equations per link end. External loads enter through them.
#include <optional>
#include <vector>

#include "elements/element_block.hpp"
#include "elements/free_directions.hpp"

namespace stiffmsa::detail {

// `kept` becomes a copy of *kinematics, or nothing where it is null (its buffers kept).
inline void from_kinematics(const Kinematics* kinematics, std::optional<Kinematics>& kept) {
  if (!kinematics)
    kept.reset();
  else if (kept)
    *kept = *kinematics;
  else
    kept.emplace(*kinematics);
}

// A rigid or passive joint over m >= 2 link ends (paper eqs. 4–8); rigid is p = 0, and so is a
// locked actuator. 6m equations:
//   Λ_r·(Δt_1 − Δt_k) = 0, k = 2..m                     r(m−1)
//   Λ_r·Σ W_k = Λ_r·Σ W_ext,k                            r
//   Λ_p·W_k = Λ_p·W_ext,k (± Λ_pΛ_pᵀ·w_0 on ends 1, 2)   p·m
class ConstraintJointBlock final : public ElementBlock {
 public:
  ConstraintJointBlock(std::vector<int> ends, FreeDirections directions,
                       std::optional<VecX> preload);
  // Another pose's numbers in place, the ends kept: a workspace's blocks keep their buffers.
  void refill(const FreeDirections& directions, const std::optional<VecX>& preload);
  Index equation_count() const override { return 6 * static_cast<Index>(ends_.size()); }
  void write_equations(Index first_row, EquationWriter& out) const override;
  void add_external_wrench(Index first_row, int end_id, const Vec6& wrench,
                           VecX& rhs) const override;
  void add_preload(Index first_row, VecX& rhs) const override;
  bool has_preload() const override { return preload_.has_value(); }
  const FreeDirections* directions() const override { return &directions_; }
  const Kinematics* kinematics() const override { return kinematics_ ? &*kinematics_ : nullptr; }
  void set_kinematics(const Kinematics* kinematics) { from_kinematics(kinematics, kinematics_); }
  const std::vector<int>& ends() const { return ends_; }
  Index r() const { return directions_.constrained().rows(); }
  Index p() const { return directions_.free().rows(); }

 private:
  std::vector<int> ends_;
  FreeDirections directions_;
  std::optional<VecX> preload_;
  std::optional<Kinematics> kinematics_;
};

// An elastic joint between two link ends (paper eqs. 9–11, spring sign per theory-notes):
//   W_1 + W_2 = W_ext,1 + W_ext,2                                       6
//   Λ_r·(Δt_1 − Δt_2) = 0                                               r
//   Λ_p·W_1 − G·K·Λ_p·(Δt_2 − Δt_1) = Λ_p·W_ext,1 + G·w_0, G = Λ_pΛ_pᵀ    p
class ElasticJointBlock final : public ElementBlock {
 public:
  ElasticJointBlock(int end_1, int end_2, FreeDirections directions, const MatX& stiffness,
                    std::optional<VecX> preload);
  void refill(const FreeDirections& directions, const MatX& stiffness,
              const std::optional<VecX>& preload);
  Index equation_count() const override { return 12; }
  void write_equations(Index first_row, EquationWriter& out) const override;
  void add_external_wrench(Index first_row, int end_id, const Vec6& wrench,
                           VecX& rhs) const override;
  void add_preload(Index first_row, VecX& rhs) const override;
  bool has_preload() const override { return preload_.has_value(); }
  const FreeDirections* directions() const override { return &directions_; }
  const Kinematics* kinematics() const override { return kinematics_ ? &*kinematics_ : nullptr; }
  void set_kinematics(const Kinematics* kinematics) { from_kinematics(kinematics, kinematics_); }
  int end_1() const { return end_1_; }
  int end_2() const { return end_2_; }
  const SmallMat& spring() const { return spring_; }
  const std::optional<VecX>& preload() const { return preload_; }

 private:
  int end_1_, end_2_;
  FreeDirections directions_;
  std::optional<Kinematics> kinematics_;
  SmallMat spring_;  // G·K·Λ_p: the same on every refill, so formed once
  std::optional<VecX> preload_;
};

// A support over m >= 1 link ends, first joined rigidly, then held as one (paper eqs. 12–16):
//   Δt_1 − Δt_k = 0, k = 2..m                                  6(m−1)
//   Λ_r·Δt_1 = 0                                               r
//   Λ_p·Σ W_k + G·K·Λ_p·Δt_1 = Λ_p·Σ W_ext,k + G·w_0            p  (K = 0 when not elastic)
class SupportBlock final : public ElementBlock {
 public:
  // `settlement`: the ground's prescribed motion along the held directions (Support::displacement),
  // written with the preload into the right-hand side of every load case.
  SupportBlock(std::vector<int> ends, FreeDirections directions,
               const std::optional<MatX>& stiffness, std::optional<VecX> preload,
               std::optional<Vec6> settlement = std::nullopt);
  void refill(const FreeDirections& directions, const std::optional<MatX>& stiffness,
              const std::optional<VecX>& preload,
              const std::optional<Vec6>& settlement = std::nullopt);
  Index equation_count() const override { return 6 * static_cast<Index>(ends_.size()); }
  void write_equations(Index first_row, EquationWriter& out) const override;
  void add_external_wrench(Index first_row, int end_id, const Vec6& wrench,
                           VecX& rhs) const override;
  void add_preload(Index first_row, VecX& rhs) const override;
  bool has_preload() const override { return preload_.has_value() || settlement_.has_value(); }
  std::optional<Vec6> settlement() const override { return settlement_; }
  const FreeDirections* directions() const override { return &directions_; }
  const Kinematics* kinematics() const override { return kinematics_ ? &*kinematics_ : nullptr; }
  void set_kinematics(const Kinematics* kinematics) { from_kinematics(kinematics, kinematics_); }
  const std::vector<int>& ends() const { return ends_; }
  // G·K·Λ_p where elastic.
  const std::optional<SmallMat>& spring() const { return spring_; }
  const std::optional<VecX>& preload() const { return preload_; }
  // Free directions and no spring: nothing holds its motion along them.
  bool passive() const { return directions_.free().rows() > 0 && !spring_; }

 private:
  std::vector<int> ends_;
  FreeDirections directions_;
  std::optional<SmallMat>
      spring_;  // G·K·Λ_p when elastic: the same on every refill, so formed once
  std::optional<VecX> preload_;
  std::optional<Vec6> settlement_;
  std::optional<Kinematics> kinematics_;
};

// A link end alone at its point and named nowhere: W = W_ext.
class FreeEndBlock final : public ElementBlock {
 public:
  explicit FreeEndBlock(int end) : ElementBlock(BlockKind::free_end), end_(end) {}
  Index equation_count() const override { return 6; }
  void write_equations(Index first_row, EquationWriter& out) const override;
  void add_external_wrench(Index first_row, int end_id, const Vec6& wrench,
                           VecX& rhs) const override;
  int end() const { return end_; }

 private:
  int end_;
};

}  // namespace stiffmsa::detail
