#pragma once
// A URDF file's kinematic tree, as the robot block of a model file (docs/urdf.md) uses it.
// urdfdom builds the kinematic model; TinyXML, which urdfdom parses with, gives each link and
// joint its line, so that every message names the place in the URDF.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "stiffmsa/errors.hpp"
#include "stiffmsa/types.hpp"

namespace stiffmsa::detail {

enum class UrdfJointType { revolute, continuous, prismatic, fixed };

// A rigid transform: x ↦ rotation·x + translation.
struct Placement {
  Mat3 rotation = Mat3::Identity();
  Vec3 translation = Vec3::Zero();

  Placement operator*(const Placement& inner) const {
    return {rotation * inner.rotation, rotation * inner.translation + translation};
  }
  Vec3 apply(const Vec3& x) const { return rotation * x + translation; }
  Placement inverse() const {
    return {rotation.transpose(), -(rotation.transpose() * translation)};
  }
};

struct UrdfJoint {
  std::string name;
  UrdfJointType type = UrdfJointType::fixed;
  int parent = -1;  // link indices
  int child = -1;
  Placement origin;                    // the joint frame in the parent's frame at zero position
  Vec3 axis = Vec3::UnitX();           // unit, in the joint frame (the child's frame)
  std::optional<double> lower, upper;  // revolute and prismatic limits
  SourceLocation location;
};

struct UrdfLink {
  std::string name;
  double mass = 0;
  Vec3 centre_of_mass = Vec3::Zero();  // in the link's frame
  int parent_joint = -1;               // -1 for the root
  std::vector<int> child_joints;       // in the file's order
  SourceLocation location;
};

struct UrdfTree {
  std::string file;
  std::string name;
  std::vector<UrdfLink> links;    // the root first, every link after its parent
  std::vector<UrdfJoint> joints;  // every joint after the joint of its parent link
  std::optional<int> find_link(const std::string& name) const;
  std::optional<int> find_joint(const std::string& name) const;
  std::vector<std::string> link_names() const;
  std::vector<std::string> joint_names() const;
};

bool is_movable(UrdfJointType type);
const char* to_string(UrdfJointType type);

// Reads a URDF file. Throws InputError naming the file and line of what is wrong, or, where
// the file cannot be read, `referenced_at` and `key`: the model file's `urdf:`.
UrdfTree read_urdf(const std::filesystem::path& path, const SourceLocation& referenced_at,
                   const std::string& key);

}  // namespace stiffmsa::detail
