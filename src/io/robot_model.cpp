#include "io/robot_model.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <sstream>

namespace stiffmsa::detail {
namespace {

// Where the centre of mass of a flexible link projects on its beam, as a fraction of the beam:
// kept this far inside, so that both parts of the split beam have a length.
constexpr double kMassFootMargin = 0.01;

// The frame of each URDF link in the root's frame at the given joint positions.
std::vector<Placement> root_placements(const UrdfTree& tree, std::span<const double> positions) {
  std::vector<Placement> frames(tree.links.size());
  for (std::size_t j = 0; j < tree.joints.size(); ++j) {
    const UrdfJoint& joint = tree.joints[j];
    Placement motion;
    const double q = positions[j];
    if (joint.type == UrdfJointType::revolute || joint.type == UrdfJointType::continuous)
      motion.rotation = Eigen::AngleAxisd(q, joint.axis).toRotationMatrix();
    else if (joint.type == UrdfJointType::prismatic)
      motion.translation = q * joint.axis;
    frames[static_cast<std::size_t>(joint.child)] =
        frames[static_cast<std::size_t>(joint.parent)] * joint.origin * motion;
  }
  return frames;
}

std::string number_text(double x) {
  std::ostringstream s;
  s.precision(6);
  s << x;
  return s.str();
}

}  // namespace

std::size_t RobotLayout::add_point(Model& model, std::string name, int link, const Vec3& local,
                                   const SourceLocation& at) {
  Point& p = model.point(model.add_point(std::move(name), Vec3::Zero()));
  p.origin.location = at;
  points_.push_back({model.points.size() - 1, link, local});
  return model.points.size() - 1;
}

RobotLayout::RobotLayout(const RobotBlock& block, Model& model)
    : tree_(block.tree), base_(block.base), position_at_(block.position_at) {
  const UrdfTree& tree = *tree_;
  const std::size_t n = tree.links.size();
  included_.assign(n, false);
  leaf_.assign(n, false);
  frame_ends_.resize(n);
  // The base's subtree is the robot; what lies above the base (the `world` link of ROS URDFs)
  // must hold it through fixed joints alone, with nothing else attached.
  included_[static_cast<std::size_t>(base_)] = true;
  for (std::size_t l = 0; l < n; ++l) {
    const int parent_joint = tree.links[l].parent_joint;
    if (parent_joint >= 0 && included_[static_cast<std::size_t>(
                                 tree.joints[static_cast<std::size_t>(parent_joint)].parent)])
      included_[l] = true;
  }
  for (int l = tree.links[static_cast<std::size_t>(base_)].parent_joint; l >= 0;) {
    const UrdfJoint& above = tree.joints[static_cast<std::size_t>(l)];
    const UrdfLink& parent = tree.links[static_cast<std::size_t>(above.parent)];
    if (is_movable(above.type) || parent.child_joints.size() != 1)
      throw InputError(above.location, "robot.base",
                       "the base '" + tree.links[static_cast<std::size_t>(base_)].name +
                           "' is not the URDF's root link and '" + parent.name + "' above it " +
                           (is_movable(above.type) ? "moves it through joint '" + above.name + "'"
                                                   : "carries other joints as well") +
                           "; choose the root link '" + tree.links.front().name +
                           "' as the base, or a link held by fixed joints alone");
    l = parent.parent_joint;
  }

  const auto name_of = [&](int link) -> const std::string& {
    return tree.links[static_cast<std::size_t>(link)].name;
  };
  // Each URDF link's point at its frame's origin, where its parent joint is.
  std::vector<std::size_t> frame_point(n);
  for (std::size_t l = 0; l < n; ++l)
    if (included_[l])
      frame_point[l] = add_point(model, tree.links[l].name, static_cast<int>(l), Vec3::Zero(),
                                 tree.links[l].location);

  // The link whose end meets each child joint, by URDF joint.
  std::vector<std::string> segment_into(tree.joints.size());
  for (std::size_t l = 0; l < n; ++l) {
    if (!included_[l]) continue;
    const UrdfLink& link = tree.links[l];
    const int li = static_cast<int>(l);
    const auto& children = link.child_joints;
    const auto child_point = [&](int joint) -> const std::string& {
      return name_of(tree.joints[static_cast<std::size_t>(joint)].child);
    };
    const std::optional<FlexibleLink>& flexible = block.flexible[l];
    if (flexible && children.size() != 1)
      throw InputError(flexible->origin.location, "robot.links." + link.name,
                       "link '" + link.name + "' has " + std::to_string(children.size()) +
                           " child joints: a flexible link runs from its frame's origin to its one "
                           "child joint's origin");
    if (flexible && li == base_)
      throw InputError(flexible->origin.location, "robot.links." + link.name,
                       "link '" + link.name +
                           "' is the base, which a rigid support holds: it cannot be flexible");
    frame_ends_[l] = {link.name, link.name, Vec3::Zero()};
    const bool welded_leaf =
        children.empty() && li != base_ && link.parent_joint >= 0 &&
        !is_movable(tree.joints[static_cast<std::size_t>(link.parent_joint)].type);
    if (welded_leaf) {
      // A frame fixed at the end of a chain (ROS's tool0) is a place on its parent's link: the
      // parent's link end there is its end, and no link of its own costs a solve 24 unknowns.
      leaf_[l] = true;
      frame_ends_[l].link = segment_into[static_cast<std::size_t>(link.parent_joint)];
    } else if (children.empty()) {
      leaf_[l] = true;
      add_point(model, link.name + ".end", li, Vec3::Zero(), link.location);
      model.link(model.add_rigid_link(link.name, link.name, link.name + ".end")).origin.location =
          link.location;
      frame_ends_[l].point = link.name + ".end";
    } else if (children.size() == 1 && flexible) {
      const UrdfJoint& child = tree.joints[static_cast<std::size_t>(children.front())];
      const Vec3 along = child.origin.translation;
      Vec3 zref = Vec3::UnitZ();
      if (along.cross(zref).norm() <= 1e-9 * along.norm()) zref = Vec3::UnitX();
      const bool split = block.gravity && link.mass > 0 && along.norm() > 0;
      std::string end_point = child_point(children.front());
      if (split) {
        const double s = std::clamp(link.centre_of_mass.dot(along) / along.squaredNorm(),
                                    kMassFootMargin, 1 - kMassFootMargin);
        add_point(model, link.name + ".com", li, s * along, link.location);
        end_point = link.name + ".com";
      }
      const auto add_beam = [&](std::string name, std::string from, std::string to) {
        Link& beam = model.link(model.add_beam(std::move(name), std::move(from), std::move(to),
                                               flexible->beam.material, flexible->beam.section));
        std::get<BeamLink>(beam.kind) = flexible->beam;
        std::get<BeamLink>(beam.kind).zref = Vec3::Zero();
        beam.origin = flexible->origin;
        beams_.push_back({model.links.size() - 1, li, zref});
      };
      add_beam(link.name, link.name, end_point);
      segment_into[static_cast<std::size_t>(children.front())] = link.name;
      if (split) {
        add_beam(link.name + ".distal", link.name + ".com", child_point(children.front()));
        segment_into[static_cast<std::size_t>(children.front())] = link.name + ".distal";
        loads_.push_back({model.loads.size(), li, link.centre_of_mass - points_.back().local,
                          (Vec6() << link.mass * *block.gravity, Vec3::Zero()).finished(), false});
        Load& weight = model.load(model.add_load(link.name + ".com", link.name, Vec6::Zero()));
        weight.self_weight = true;
        weight.origin.location = link.location;
      }
    } else if (children.size() == 1) {
      model.link(model.add_rigid_link(link.name, link.name, child_point(children.front())))
          .origin.location = link.location;
      segment_into[static_cast<std::size_t>(children.front())] = link.name;
    } else {
      // Several child joints meet the link's body at a hub, so that its parent joint joins two
      // link ends, as an elastic joint must.
      std::string hub = link.name;
      if (li != base_) {
        hub = link.name + ".hub";
        add_point(model, hub, li, Vec3::Zero(), link.location);
        model.link(model.add_rigid_link(link.name, link.name, hub)).origin.location = link.location;
      }
      for (int j : children) {
        const std::string segment = link.name + "/" + tree.joints[static_cast<std::size_t>(j)].name;
        model.link(model.add_rigid_link(segment, hub, child_point(j))).origin.location =
            link.location;
        segment_into[static_cast<std::size_t>(j)] = segment;
      }
      if (li == base_)
        frame_ends_[l].link =
            link.name + "/" + tree.joints[static_cast<std::size_t>(children.front())].name;
    }
    // A rigid link's weight acts at its frame's end, with the moment of its lever.
    const bool split_flexible = flexible && block.gravity && link.mass > 0;
    if (block.gravity && link.mass > 0 && li != base_ && !split_flexible) {
      loads_.push_back({model.loads.size(), li, link.centre_of_mass - frame_ends_[l].local,
                        (Vec6() << link.mass * *block.gravity, Vec3::Zero()).finished(), false});
      Load& weight =
          model.load(model.add_load(frame_ends_[l].point, frame_ends_[l].link, Vec6::Zero()));
      weight.self_weight = true;
      weight.origin.location = link.location;
    }
  }

  for (std::size_t j = 0; j < tree.joints.size(); ++j) {
    const UrdfJoint& joint = tree.joints[j];
    if (!included_[static_cast<std::size_t>(joint.child)] ||
        !included_[static_cast<std::size_t>(joint.parent)])
      continue;
    // A fixed joint is no joint: the link ends that meet at its point, named by nothing, are
    // welded.
    if (!is_movable(joint.type)) continue;
    const std::string& at = name_of(joint.child);
    const JointSpring& spring = block.springs[j];
    Connection c;
    if (spring.compliance) {
      c.kinematics = Kinematics::custom(std::vector<Vec6>(6, Vec6::Zero()));  // turned by pose()
      c.stiffness = MatX(spring.compliance->inverse());
    } else {
      c.kinematics = joint.type == UrdfJointType::prismatic ? Kinematics::prismatic(Vec3::UnitX())
                                                            : Kinematics::revolute(Vec3::UnitX());
      c.stiffness = MatX::Constant(1, 1, spring.stiffness);
    }
    Joint& made = model.joint(model.add_joint(joint.name, at, {segment_into[j], at}, std::move(c)));
    made.origin = spring.origin;
    made.origin.location = joint.location;
    joints_.push_back({model.joints.size() - 1, static_cast<int>(j)});
  }
  model.support(model.add_support(name_of(base_), name_of(base_), {}, Connection::rigid()))
      .origin.location = tree.links[static_cast<std::size_t>(base_)].location;
  std::vector<double> zero(tree.joints.size(), 0.0);
  pose(zero, model);
}

std::optional<std::string> RobotLayout::add_end_effector(std::string name, int frame,
                                                         const std::optional<Vec3>& offset,
                                                         bool frame_axes, Origin origin,
                                                         Model& model) {
  const FrameEnd& end = frame_ends_[static_cast<std::size_t>(frame)];
  const std::string& frame_name = tree_->links[static_cast<std::size_t>(frame)].name;
  if (!in_robot(frame))
    return "frame '" + frame_name + "' lies above the base '" +
           tree_->links[static_cast<std::size_t>(base_)].name + "'";
  if (frame_axes) effectors_.push_back({model.end_effectors.size(), frame});
  if (!offset) {
    EndEffector& e =
        model.end_effector(model.add_end_effector(std::move(name), end.point, end.link));
    e.origin = std::move(origin);
    return std::nullopt;
  }
  if (!leaf_[static_cast<std::size_t>(frame)]) {
    if (frame_axes) effectors_.pop_back();
    return "an offset needs a frame at the end of a chain, where nothing else is attached; '" +
           frame_name +
           "' has child joints (ROS URDFs attach a `tool0` link by a fixed joint for this)";
  }
  const std::string tcp = name + ".tcp";
  add_point(model, tcp, frame, *offset, origin.location);
  model.link(model.add_rigid_link(tcp, end.point, tcp)).origin.location = origin.location;
  tool_links_.push_back({tcp, frame, *offset, model.end_effectors.size()});
  EndEffector& e = model.end_effector(model.add_end_effector(std::move(name), tcp, tcp));
  e.origin = std::move(origin);
  return std::nullopt;
}

std::optional<std::string> RobotLayout::add_load(int frame, const Vec6& wrench,
                                                 const std::optional<Vec3>& offset, bool frame_axes,
                                                 Origin origin, Model& model) {
  if (!in_robot(frame))
    return "frame '" + tree_->links[static_cast<std::size_t>(frame)].name +
           "' lies above the base '" + tree_->links[static_cast<std::size_t>(base_)].name + "'";
  const FrameEnd& end = frame_ends_[static_cast<std::size_t>(frame)];
  loads_.push_back(
      {model.loads.size(), frame, offset.value_or(Vec3::Zero()) - end.local, wrench, frame_axes});
  Load& load = model.load(model.add_load(end.point, end.link, Vec6::Zero()));
  load.origin = std::move(origin);
  return std::nullopt;
}

void RobotLayout::fold_tool_links(Model& model) {
  for (const ToolLink& tool : tool_links_) {
    FrameEnd& end = frame_ends_[static_cast<std::size_t>(tool.frame)];
    const std::string point = end.point;
    const auto reaching = std::find_if(model.links.begin(), model.links.end(),
                                       [&](const Link& l) { return l.name == end.link; });
    // A beam's length is its stiffness: only a rigid link may run on.
    if (reaching == model.links.end() || reaching->to != point ||
        !std::holds_alternative<RigidLink>(reaching->kind))
      continue;
    // Anything else attached at the frame's point needs the point as a link end: no fold there.
    const auto is_tool_link = [&](const Link& l) {
      return l.from == point && std::any_of(tool_links_.begin(), tool_links_.end(),
                                            [&](const ToolLink& t) { return t.link == l.name; });
    };
    const auto carried_here = [&](std::size_t load) {
      return std::any_of(loads_.begin(), loads_.end(), [&](const CarriedLoad& c) {
        return c.load == load && c.link == tool.frame;
      });
    };
    bool alone = true;
    for (const Link& l : model.links)
      if ((l.from == point || l.to == point) && &l != &*reaching && !is_tool_link(l)) alone = false;
    for (const Joint& j : model.joints) alone = alone && j.at != point;
    for (const Support& s : model.supports) alone = alone && s.at != point;
    for (const EndEffector& e : model.end_effectors) alone = alone && e.at != point;
    for (std::size_t k = 0; k < model.loads.size(); ++k)
      if (model.loads[k].at == point && !carried_here(k)) alone = false;
    if (!alone) continue;

    // The frame's point stays, posed with the robot, with no link end at it.
    const Link* tool_link = model.find_link(tool.link);
    if (!tool_link) continue;
    const std::string tcp = tool_link->to;
    reaching->to = tcp;
    model.end_effectors[tool.effector].link = reaching->name;
    for (Link& l : model.links)
      if (is_tool_link(l)) l.from = tcp;
    for (CarriedLoad& c : loads_)
      if (model.loads[c.load].at == point) {
        model.loads[c.load].at = tcp;
        c.lever -= tool.local - end.local;
      }
    end.point = tcp;
    end.local = tool.local;
    // Tool links are the model's last links (end effectors are read last): no index above it moves.
    std::erase_if(model.links, [&](const Link& l) { return l.name == tool.link; });
  }
}

void RobotLayout::pose(std::span<const double> positions, Model& model) const {
  const UrdfTree& tree = *tree_;
  std::vector<Placement> frames = root_placements(tree, positions);
  const Placement world_from_root = frames[static_cast<std::size_t>(base_)].inverse();
  for (auto& f : frames) f = world_from_root * f;
  const auto frame = [&](int link) -> const Placement& {
    return frames[static_cast<std::size_t>(link)];
  };
  for (const PlacedPoint& p : points_)
    model.points[p.point].position = frame(p.link).apply(p.local);
  for (const TurningJoint& j : joints_) {
    const UrdfJoint& joint = tree.joints[static_cast<std::size_t>(j.urdf_joint)];
    Kinematics& k = model.joints[j.joint].connection.kinematics;
    const Mat3& r = frame(joint.child).rotation;
    if (k.type == JointType::custom) {
      for (int i = 0; i < 3; ++i) {
        k.free_rows[static_cast<std::size_t>(i)] << r.col(i), Vec3::Zero();
        k.free_rows[static_cast<std::size_t>(i + 3)] << Vec3::Zero(), r.col(i);
      }
    } else {
      k.axis = r * joint.axis;
    }
  }
  for (const TurningEffector& e : effectors_)
    model.end_effectors[e.effector].axes = frame(e.link).rotation;
  for (const TurningBeam& b : beams_)
    std::get<BeamLink>(model.links[b.link].kind).zref = frame(b.urdf_link).rotation * b.zref;
  for (const CarriedLoad& l : loads_) {
    const Mat3& r = frame(l.link).rotation;
    Vec3 force = l.wrench.head<3>();
    Vec3 moment = l.wrench.tail<3>();
    if (l.frame_axes) {
      force = r * force;
      moment = r * moment;
    }
    model.loads[l.load].wrench << force, moment + (r * l.lever).cross(force);
  }
  model.warnings.clear();
  for (std::size_t j = 0; j < tree.joints.size(); ++j) {
    const UrdfJoint& joint = tree.joints[j];
    const double q = positions[j];
    if (!joint.lower || !joint.upper || !included_[static_cast<std::size_t>(joint.child)]) continue;
    if (q >= *joint.lower && q <= *joint.upper) continue;
    const char* unit = joint.type == UrdfJointType::prismatic ? " m" : " rad";
    model.warnings.push_back({position_at_[j], "robot.positions." + joint.name,
                              "the position " + number_text(q) + unit + " of joint '" + joint.name +
                                  "' is outside its limits [" + number_text(*joint.lower) + ", " +
                                  number_text(*joint.upper) + "]" + unit + " (" + tree.file +
                                  ", line " + std::to_string(joint.location.line) + ")"});
  }
}

}  // namespace stiffmsa::detail
