#pragma once
// The element blocks of the loaded mode (docs/theory.md §15): each writes the same rows as its
// linear block (§3, §4), as residuals of the deformed geometry, and their exact derivatives, the
// Newton tangent. The unknowns of link end k are its current position x_k, the rotation R_k
// that has turned it from the unloaded pose and its wrench W_k = [F; M] (moment about x_k);
// an increment is [δx; δθ; δW] with δθ a small rotation in global axes, R_k ← exp([δθ×])·R_k,
// so that the tangent has the linear system's 12 columns per link end, in its order.
#include <memory>
#include <optional>
#include <variant>
#include <vector>

#include "elements/beam_element.hpp"
#include "elements/element_block.hpp"
#include "elements/free_directions.hpp"

namespace stiffmsa::detail {

struct EndState {
  Vec3 position = Vec3::Zero();
  Mat3 rotation = Mat3::Identity();
  Vec6 wrench = Vec6::Zero();
};

// What a block reads besides its ends' states: the external wrenches at every link end and the
// load factor λ, both of the current load step (preloads and settlements are taken times λ;
// `external` already is).
struct LoadedInputs {
  const std::vector<EndState>& ends;
  const std::vector<Vec6>& external;
  double load_factor = 1;
};

class LoadedBlock {
 public:
  virtual ~LoadedBlock() = default;
  virtual Index equation_count() const = 0;
  // The link ends whose unknowns the rows involve, in the order of the tangent's columns.
  virtual const std::vector<int>& ends() const = 0;
  // What else, besides equation_count() and ends(), decides where the block writes into its
  // tangent (its kind, a joint's free directions): a tangent of one pose's block is handed to
  // the next pose's block in its place where the two agree in all three (LoadedTangent).
  virtual int pattern() const { return 0; }
  // The residual rows, and where `tangent` is given their derivatives (equation_count() ×
  // 12·ends().size(), 12 columns per end: δx, δθ, δW). A `tangent` of another size is sized and
  // zeroed; one of that size must be zero wherever this block writes nothing (as it is after
  // this block's own last evaluation): the block then writes only its pattern, not the whole
  // matrix again.
  virtual void evaluate(const LoadedInputs& in, Eigen::Ref<VecX> residual, MatX* tangent) const = 0;
};

// A flexible link as a co-rotational element (§15.2): the energy ½·d̄ᵀ·K·d̄ of its free-free
// stiffness K (global axes of the unloaded pose) over the deformation d̄ left once the link's
// rigid motion is taken out; a beam adds the shortening of its chord by bending (`axial`).
// Rows: W_i − ∂E/∂t_i, W_j − ∂E/∂t_j.
struct CorotationalLink {
  Mat12 stiffness;
  Vec3 d0;                      // p_to − p_from, unloaded
  std::optional<double> axial;  // E·A of a beam
};
std::unique_ptr<LoadedBlock> make_corotational_link(int end_i, int end_j,
                                                    const CorotationalLink& link);

// A rigid link (§15.3): x_j = x_i + R_i·d0, R_j = R_i, and its balance about x_i.
std::unique_ptr<LoadedBlock> make_loaded_rigid_link(int end_i, int end_j, const Vec3& d0);

// A rigid, passive (or locked) joint over m ≥ 2 link ends (§15.4): its free and constrained
// directions turn with its first end.
std::unique_ptr<LoadedBlock> make_loaded_constraint_joint(std::vector<int> ends,
                                                          const FreeDirections& directions,
                                                          const std::optional<VecX>& preload);

// An elastic joint between two link ends (§15.4): the spring acts on the finite relative
// motion (a revolute joint's finite angle).
std::unique_ptr<LoadedBlock> make_loaded_elastic_joint(int end_1, int end_2,
                                                       const FreeDirections& directions,
                                                       const MatX& stiffness,
                                                       const std::optional<VecX>& preload);

// A support over m ≥ 1 link ends (§15.5): the ground's directions do not turn; a settlement
// moves the ground by λ·s.
std::unique_ptr<LoadedBlock> make_loaded_support(std::vector<int> ends,
                                                 const FreeDirections& directions,
                                                 const std::optional<MatX>& stiffness,
                                                 const std::optional<VecX>& preload,
                                                 const std::optional<Vec6>& settlement,
                                                 const Vec3& unloaded_position);

// A free end: W = W_ext.
std::unique_ptr<LoadedBlock> make_loaded_free_end(int end);

}  // namespace stiffmsa::detail

namespace stiffmsa::detail {

// ---- loads along links (docs/theory.md §15.9) ----------------------------------------------

// A dead load along a link: global axes, per metre of unloaded length (model.hpp).
using LoadAlongLink = std::variant<DistributedLinkLoad, PointLinkLoad>;

// Where a link's points are in the loaded mode: a rigid link's at x_i + ξ·R_i·d0; a beam's on
// its chord plus the transverse shape of its ends' slopes across it (the shapes of §12.1, shear
// included); any other link's on its chord.
class LoadedLinkShape {
 public:
  enum class Kind { rigid, beam, chord };
  LoadedLinkShape(const Link& link, const Vec3& from, const Vec3& to);
  // The point at fraction ξ of the length from the `from` end, ends i (`from`) and j (`to`).
  Vec3 point(const EndState& i, const EndState& j, double xi) const;
  // The link's local axes turned with it (rows, global components): a beam's co-rotated axes
  // (x along the chord), a rigid link's turned by R_i.
  Mat3 axes(const EndState& i, const EndState& j) const;

  Kind kind() const { return kind_; }
  double length() const { return length_; }
  const Vec3& unloaded_chord() const { return d0_; }
  const Mat3& unloaded_axes() const { return axes_; }  // rows
  const BeamConstants& constants() const { return constants_; }

 private:
  Kind kind_ = Kind::chord;
  Vec3 d0_;
  double length_ = 0;
  Mat3 axes_ = Mat3::Identity();
  BeamConstants constants_;
};

// The link's loaded block with the dead loads along it (times the load factor) added to its rows
// with their exact derivatives: a flexible link's end rows W − ∂E/∂t gain the clamp wrenches
// (the gradient of the loads' potential over the link's current shape; a beam's point moments
// as fixed-end wrenches turned with its co-rotated frame), a rigid link's balance rows the
// loads' resultant about x_i. `link_block` unchanged where there is no load.
std::unique_ptr<LoadedBlock> with_loads_along(std::unique_ptr<LoadedBlock> link_block,
                                              const Link& link, const Vec3& from, const Vec3& to,
                                              const std::vector<LoadAlongLink>& loads);

}  // namespace stiffmsa::detail
