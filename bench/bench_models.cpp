#include "bench_models.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace bench {

using stiffmsa::Connection;
using stiffmsa::Link;
using stiffmsa::Material;
using stiffmsa::Section;
using stiffmsa::Vec6;

namespace {

constexpr double kPi = std::numbers::pi;

// The position of a named point, writable when the model is.
template <class AnyModel>
auto& position(AnyModel& model, const std::string& point) {
  for (auto& p : model.points)
    if (p.name == point) return p.position;
  throw std::runtime_error("bench: no point '" + point + "' in model '" + model.name + "'");
}

stiffmsa::Kinematics& kinematics_of_joint(Model& model, const std::string& joint) {
  for (auto& j : model.joints)
    if (j.name == joint) return j.connection.kinematics;
  throw std::runtime_error("bench: no joint '" + joint + "' in model '" + model.name + "'");
}

const stiffmsa::Kinematics& kinematics_of_support(const Model& model, const std::string& support) {
  for (const auto& s : model.supports)
    if (s.name == support) return s.connection.kinematics;
  throw std::runtime_error("bench: no support '" + support + "' in model '" + model.name + "'");
}

// prefix + number; built by appending, which also avoids GCC 12's false -Wrestrict warning on
// "literal" + std::to_string(...).
std::string numbered(std::string prefix, int number) {
  prefix += std::to_string(number);
  return prefix;
}

// Phase of pose p of `count`, in [0, 2π).
double phase(int p, int count) { return 2 * kPi * p / count; }

}  // namespace

Model load_example(const std::string& file) {
  return stiffmsa::load_model(std::string(STIFFMSA_EXAMPLES_DIR) + "/" + file);
}

std::vector<Model> industrial_poses(const Model& home, int count) {
  // The points along the chain, base first: the links are listed base to tool, each starting
  // where the previous one ends.
  std::vector<std::string> chain{home.links.front().from};
  for (const Link& link : home.links) {
    if (link.from != chain.back())
      throw std::runtime_error("bench: the links are not listed base to tool");
    chain.push_back(link.to);
  }
  auto place_in_chain = [&](const std::string& point) {
    for (std::size_t i = 0; i < chain.size(); ++i)
      if (chain[i] == point) return i;
    throw std::runtime_error("bench: joint point '" + point + "' is not on the chain");
  };
  const double amplitude[] = {0.3, 0.2, 0.2, 0.3, 0.2, 0.3};
  if (home.joints.size() != std::size(amplitude))
    throw std::runtime_error("bench: expected six joints");

  std::vector<Model> poses;
  for (int p = 0; p < count; ++p) {
    Model m = home;
    // Product of exponentials: turn joint k (about its axis in the file's pose) from the tool
    // back to the base; each turn moves the points and the joint axes beyond joint k.
    for (int k = static_cast<int>(home.joints.size()) - 1; k >= 0; --k) {
      const auto& joint = home.joints[static_cast<std::size_t>(k)];
      const Vec3 origin = position(home, joint.at);
      const double q = amplitude[k] * std::sin(phase(p, count) + 1.3 * k);
      const Eigen::AngleAxisd turn(q, joint.connection.kinematics.axis.normalized());
      for (std::size_t i = place_in_chain(joint.at) + 1; i < chain.size(); ++i) {
        Vec3& point = position(m, chain[i]);
        point = origin + turn * (point - origin);
      }
      for (std::size_t j = static_cast<std::size_t>(k) + 1; j < m.joints.size(); ++j)
        m.joints[j].connection.kinematics.axis = turn * m.joints[j].connection.kinematics.axis;
    }
    poses.push_back(std::move(m));
  }
  return poses;
}

std::vector<Model> gough_stewart_poses(const Model& home, int count) {
  const Vec3 centre = position(home, "centre");
  std::vector<Model> poses;
  for (int p = 0; p < count; ++p) {
    const double f = phase(p, count);
    const Vec3 shift = 0.02 * Vec3(std::sin(f), std::cos(f), 0.5 * std::sin(2 * f));
    const Eigen::AngleAxisd turn(0.05 * std::sin(f), Vec3::UnitZ());
    Model m = home;
    for (int leg = 1; leg <= 6; ++leg) {
      const Vec3 base = position(home, numbered("B", leg));
      const Vec3 top = centre + shift + turn * (position(home, numbered("P", leg)) - centre);
      position(m, numbered("P", leg)) = top;
      position(m, numbered("M", leg)) = 0.5 * (base + top);
      kinematics_of_joint(m, numbered("actuator_", leg)).axis = top - base;
    }
    position(m, "centre") = centre + shift;
    poses.push_back(std::move(m));
  }
  return poses;
}

std::vector<Model> tripteron_poses(const Model& home, int count) {
  std::vector<Model> poses;
  for (int p = 0; p < count; ++p) {
    const double f = phase(p, count);
    const Vec3 shift = 0.02 * Vec3(std::sin(f), std::cos(f), 0.5 * std::sin(2 * f));
    Model m = home;
    for (const std::string leg : {"x", "y", "z"}) {
      const Vec3 rail = kinematics_of_support(home, "screw_" + leg).axis.normalized();
      const Vec3 along = shift.dot(rail) * rail;  // the carriage follows the platform on its rail
      const Vec3 shoulder0 = position(home, "shoulder_" + leg),
                 elbow0 = position(home, "elbow_" + leg);
      const Vec3 wrist0 = position(home, "wrist_" + leg);
      const Vec3 shoulder = shoulder0 + along, wrist = wrist0 + shift;
      position(m, "slide_" + leg) += along;
      position(m, "shoulder_" + leg) = shoulder;
      position(m, "wrist_" + leg) = wrist;
      // Planar two-link inverse kinematics in the plane square to the rail: the elbow is at
      // l1 from the shoulder and l2 from the wrist, on the side it is in the file.
      const double l1 = (elbow0 - shoulder0).norm(), l2 = (wrist0 - elbow0).norm();
      const Vec3 reach = wrist - shoulder, reach0 = wrist0 - shoulder0;
      const double d = reach.norm();
      const double a = (l1 * l1 - l2 * l2 + d * d) / (2 * d);
      const double h = std::sqrt(l1 * l1 - a * a);
      const Vec3 side = rail.cross(reach / d);
      const double sign = (elbow0 - shoulder0).dot(rail.cross(reach0)) >= 0 ? 1.0 : -1.0;
      position(m, "elbow_" + leg) = shoulder + a * reach / d + sign * h * side;
    }
    position(m, "centre") += shift;
    poses.push_back(std::move(m));
  }
  return poses;
}

Model with_rigid_links(Model model) {
  for (auto& link : model.links) link.kind = stiffmsa::RigidLink{};
  return model;
}

VirtualJointModel virtual_joint_model(const Model& serial) {
  VirtualJointModel vjm;
  for (const auto& joint : serial.joints) {
    const auto& c = joint.connection;
    if (c.kinematics.type != stiffmsa::JointType::revolute || !c.stiffness ||
        c.stiffness->size() != 1)
      throw std::runtime_error("bench: the VJM needs elastic revolute joints; '" + joint.name +
                               "' is not one");
    vjm.axes.push_back(c.kinematics.axis.normalized());
    vjm.points.push_back(position(serial, joint.at));
    vjm.stiffness.push_back((*c.stiffness)(0, 0));
  }
  vjm.end_effector = position(serial, serial.end_effectors.at(0).at);
  return vjm;
}

Mat6 vjm_compliance(const VirtualJointModel& vjm) {
  Mat6 c = Mat6::Zero();
  for (std::size_t i = 0; i < vjm.axes.size(); ++i) {
    Vec6 j;
    j << vjm.axes[i].cross(vjm.end_effector - vjm.points[i]), vjm.axes[i];
    c.noalias() += (j / vjm.stiffness[i]) * j.transpose();
  }
  return c;
}

Model cantilever_chain(int links, const ChainSpec& spec) {
  Model m;
  m.name = numbered("chain-", links);
  const Material steel{spec.E, std::nullopt, spec.G};
  const Section tube = Section::tube(spec.D, spec.t);
  m.points.reserve(static_cast<std::size_t>(links) + 1);
  m.links.reserve(static_cast<std::size_t>(links));
  m.add_point("P0", Vec3::Zero());
  for (int i = 1; i <= links; ++i) {
    m.add_point(numbered("P", i), Vec3(spec.length * i / links, 0, 0));
    m.add_beam(numbered("L", i), numbered("P", i - 1), numbered("P", i), steel, tube);
  }
  m.add_support("clamp", "P0", {}, Connection::rigid());
  const std::string tip = numbered("P", links);
  m.add_load(tip, std::nullopt, (Vec6() << 0, -100, 0, 0, 0, 0).finished());
  m.add_end_effector("tip", tip);
  return m;
}

Mat6 cantilever_tip_compliance(const ChainSpec& s) {
  const double d = s.D - 2 * s.t, L = s.length;
  const double A = kPi * (s.D * s.D - d * d) / 4;
  const double I = kPi * (std::pow(s.D, 4) - std::pow(d, 4)) / 64, J = 2 * I;
  Mat6 c = Mat6::Zero();
  c(0, 0) = L / (s.E * A);
  c(1, 1) = c(2, 2) = L * L * L / (3 * s.E * I);
  c(3, 3) = L / (s.G * J);
  c(4, 4) = c(5, 5) = L / (s.E * I);
  c(1, 5) = c(5, 1) = L * L / (2 * s.E * I);
  c(2, 4) = c(4, 2) = -L * L / (2 * s.E * I);
  return c;
}

double scaled_difference(const Mat6& actual, const Mat6& expected) {
  double worst = 0;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      const double scale = std::sqrt(std::abs(expected(i, i) * expected(j, j)));
      worst = std::max(worst, std::abs(actual(i, j) - expected(i, j)) / scale);
    }
  return worst;
}

Model space_frame(int nx, int ny, int storeys) {
  const double bay = 4.0, storey_height = 3.5;
  const Material steel{2.1e11, 0.3, std::nullopt};
  const Section column = Section::rect_tube(0.3, 0.3, 0.012);
  const Section girder = Section::rect_tube(0.2, 0.35, 0.01);
  // Names: node "n<i>_<j>_<k>"; columns "cn…", x beams "xn…" and y beams "yn…" start at a node.
  auto name = [](const char* prefix, int i, int j, int k) {
    return numbered(numbered(numbered(prefix, i) + "_", j) + "_", k);
  };
  auto node = [&](int i, int j, int k) { return name("n", i, j, k); };
  Model m;
  m.name = numbered(numbered(numbered("frame-", nx) + "x", ny) + "x", storeys);
  for (int k = 0; k <= storeys; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        m.add_point(node(i, j, k), Vec3(bay * i, bay * j, storey_height * k));
  for (int k = 1; k <= storeys; ++k) {
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        m.add_beam(name("cn", i, j, k), node(i, j, k - 1), node(i, j, k), steel, column);
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i < nx; ++i)
        m.add_beam(name("xn", i, j, k), node(i, j, k), node(i + 1, j, k), steel, girder);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i <= nx; ++i)
        m.add_beam(name("yn", i, j, k), node(i, j, k), node(i, j + 1, k), steel, girder);
  }
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      m.add_support(name("gn", i, j, 0), node(i, j, 0), {}, Connection::rigid());
  const std::string corner = node(nx, ny, storeys), top_column = name("cn", nx, ny, storeys);
  m.add_load(corner, top_column, (Vec6() << 20e3, 10e3, 0, 0, 0, 0).finished());
  m.add_end_effector("roof_corner", corner, top_column);
  return m;
}

}  // namespace bench
