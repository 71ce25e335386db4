#pragma once
// The points, links, joints and support that a model file's robot block (docs/urdf.md) makes of
// a URDF, and the numbers that depend on the joint positions: the layout is made once per
// family, and each pose writes only those numbers into a member (forward kinematics).
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "io/urdf_tree.hpp"
#include "stiffmsa/model.hpp"

namespace stiffmsa::detail {

// How a movable URDF joint gives way: a spring about (along) its axis, or a 6×6 compliance in
// the joint's frame, rows [translation; rotation] at the joint's origin.
struct JointSpring {
  double stiffness = 0;
  std::optional<Mat6> compliance;
  Origin origin;  // where the model file gives it
};

// A flexible URDF link: a beam from its frame's origin to its one child joint's origin.
struct FlexibleLink {
  BeamLink beam;
  Origin origin;
};

// What the robot block says, with the URDF read.
struct RobotBlock {
  std::shared_ptr<const UrdfTree> tree;
  int base = 0;                                       // a URDF link
  std::vector<JointSpring> springs;                   // per URDF joint; unused for fixed joints
  std::vector<std::optional<FlexibleLink>> flexible;  // per URDF link
  std::optional<Vec3> gravity;
  std::vector<SourceLocation> position_at;  // per URDF joint: where its position is given
};

class RobotLayout {
 public:
  // Adds the robot's points, links, joints and the base's support to `model`. Throws
  // InputError where the URDF and the block do not make a model (a flexible link with several
  // child joints, a base with movable joints above it).
  RobotLayout(const RobotBlock& block, Model& model);

  std::size_t joint_count() const { return tree_->joints.size(); }
  const UrdfTree& tree() const { return *tree_; }

  // An end effector at the origin of URDF link `frame`, moved by `offset` in the frame's axes.
  // Returns what is wrong, if anything.
  // With `frame_axes`, its results are given in the frame's axes too.
  std::optional<std::string> add_end_effector(std::string name, int frame,
                                              const std::optional<Vec3>& offset, bool frame_axes,
                                              Origin origin, Model& model);
  // A load on URDF link `frame` at its origin moved by `offset` (frame axes); the wrench is in
  // world axes, or with `frame_axes` in the frame's.
  std::optional<std::string> add_load(int frame, const Vec6& wrench,
                                      const std::optional<Vec3>& offset, bool frame_axes,
                                      Origin origin, Model& model);

  // Writes every number that depends on the pose (positions: one per URDF joint, fixed ones
  // ignored) into a model made by this layout, and the model's warnings about positions out
  // of their joints' limits.
  void pose(std::span<const double> positions, Model& model) const;

  // Once the whole file is read: where a frame's point is only the end of the rigid link that
  // reaches it and the start of an end effector's tool link, that link runs on to the tool
  // centre point instead, as a hand-written robot's tool link does (24 unknowns fewer per pose).
  void fold_tool_links(Model& model);

 private:
  struct PlacedPoint {
    std::size_t point;
    int link;    // URDF link whose frame carries it
    Vec3 local;  // in that frame
  };
  struct TurningJoint {
    std::size_t joint;
    int urdf_joint;
  };
  struct TurningBeam {
    std::size_t link;
    int urdf_link;
    Vec3 zref;  // in the URDF link's frame
  };
  struct CarriedLoad {
    std::size_t load;
    int link;
    Vec3 lever;   // from the loaded end to where the force acts, in the link's frame
    Vec6 wrench;  // as given
    bool frame_axes = false;
  };
  struct TurningEffector {
    std::size_t effector;
    int link;
  };
  struct ToolLink {
    std::string link;  // from the frame's end point to the tool centre point
    int frame;
    Vec3 local;  // the tool centre point in the frame
    std::size_t effector;
  };
  struct FrameEnd {
    std::string point, link;
    Vec3 local = Vec3::Zero();  // the point in the frame
  };

  bool in_robot(int link) const { return included_[static_cast<std::size_t>(link)]; }
  std::size_t add_point(Model& model, std::string name, int link, const Vec3& local,
                        const SourceLocation& at);

  std::shared_ptr<const UrdfTree> tree_;
  int base_ = 0;
  std::vector<bool> included_;        // per URDF link: in the base's subtree
  std::vector<FrameEnd> frame_ends_;  // per URDF link
  std::vector<bool> leaf_;            // per URDF link
  std::vector<SourceLocation> position_at_;
  std::vector<PlacedPoint> points_;
  std::vector<TurningJoint> joints_;
  std::vector<TurningBeam> beams_;
  std::vector<CarriedLoad> loads_;
  std::vector<TurningEffector> effectors_;
  std::vector<ToolLink> tool_links_;
};

}  // namespace stiffmsa::detail
