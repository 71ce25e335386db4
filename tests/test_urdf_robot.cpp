// The robot block (docs/urdf.md): a URDF and its joints' stiffness as a model. Each test writes
// its own URDF from a table of joints and computes what the robot should do from that table,
// with forward kinematics and Jacobians of its own (virtual joint method, VJM).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "builders.hpp"
#include "stiffmsa/analysis.hpp"
#include "stiffmsa/config.hpp"
#include "stiffmsa/io/model_file.hpp"

namespace stiffmsa {
namespace {

namespace fs = std::filesystem;

// Relative agreement of the VJM formulas with the structural analysis of a robot of rigid
// links: both are exact, and the 6×6 matrices span a few orders of magnitude.
constexpr double kExact = 1e-10;

enum class Kind { revolute, continuous, prismatic, fixed };

struct TableJoint {
  std::string name;
  Kind kind;
  Vec3 xyz;  // origin in the parent frame
  Vec3 rpy;
  Vec3 axis;
  double stiffness = 0;
  double mass = 0;          // of the child link
  Vec3 com = Vec3::Zero();  // in the child's frame
};

const char* kind_name(Kind k) {
  switch (k) {
    case Kind::revolute: return "revolute";
    case Kind::continuous: return "continuous";
    case Kind::prismatic: return "prismatic";
    case Kind::fixed: return "fixed";
  }
  return "";
}

// URDF's rpy: fixed-axis roll about x, then pitch about y, then yaw about z.
Mat3 rpy_rotation(const Vec3& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Vec3::UnitX()))
      .toRotationMatrix();
}

std::string vec(const Vec3& v) {
  std::ostringstream s;
  s.precision(17);
  s << v.x() << " " << v.y() << " " << v.z();
  return s.str();
}

// A serial chain base → link_1 → ... with one joint per row; the child of row i is link_{i+1}.
std::string chain_urdf(const std::vector<TableJoint>& table, double base_mass = 0) {
  std::ostringstream u;
  u.precision(17);
  u << "<?xml version=\"1.0\"?>\n<robot name=\"chain\">\n";
  u << "  <link name=\"base\"><inertial><mass value=\"" << base_mass
    << "\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" "
       "izz=\"1\"/></inertial></link>\n";
  for (std::size_t i = 0; i < table.size(); ++i) {
    const TableJoint& j = table[i];
    u << "  <link name=\"link_" << i + 1 << "\">";
    if (j.mass > 0)
      u << "<inertial><origin xyz=\"" << vec(j.com) << "\"/><mass value=\"" << j.mass
        << "\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial>";
    u << "</link>\n";
    u << "  <joint name=\"" << j.name << "\" type=\"" << kind_name(j.kind) << "\">\n"
      << "    <parent link=\"" << (i == 0 ? std::string("base") : "link_" + std::to_string(i))
      << "\"/>\n"
      << "    <child link=\"link_" << i + 1 << "\"/>\n"
      << "    <origin xyz=\"" << vec(j.xyz) << "\" rpy=\"" << vec(j.rpy) << "\"/>\n"
      << "    <axis xyz=\"" << vec(j.axis) << "\"/>\n";
    if (j.kind == Kind::revolute || j.kind == Kind::prismatic)
      u << "    <limit lower=\"-3\" upper=\"3\" effort=\"100\" velocity=\"1\"/>\n";
    u << "  </joint>\n";
  }
  u << "</robot>\n";
  return u.str();
}

// The frames of link_1 .. link_n in the base's frame, and the world axis of each joint.
struct ChainFrames {
  std::vector<Mat3> rotation;
  std::vector<Vec3> origin;
  std::vector<Vec3> axis;
};

ChainFrames forward(const std::vector<TableJoint>& table, const std::vector<double>& q) {
  ChainFrames k;
  Mat3 r = Mat3::Identity();
  Vec3 p = Vec3::Zero();
  for (std::size_t i = 0; i < table.size(); ++i) {
    const TableJoint& j = table[i];
    p = p + r * j.xyz;
    r = r * rpy_rotation(j.rpy);
    const Vec3 a = r * j.axis.normalized();
    if (j.kind == Kind::revolute || j.kind == Kind::continuous)
      r = Eigen::AngleAxisd(q[i], a).toRotationMatrix() * r;
    if (j.kind == Kind::prismatic) p = p + q[i] * a;
    k.rotation.push_back(r);
    k.origin.push_back(p);
    k.axis.push_back(a);
  }
  return k;
}

// The geometric Jacobian at point `e` (columns of the movable joints) and their stiffness.
struct Vjm {
  MatX jacobian;
  VecX stiffness;
};

Vjm vjm(const std::vector<TableJoint>& table, const ChainFrames& k, const Vec3& e) {
  std::vector<Vec6> columns;
  std::vector<double> stiffness;
  for (std::size_t i = 0; i < table.size(); ++i) {
    const Kind kind = table[i].kind;
    if (kind == Kind::fixed) continue;
    Vec6 c;
    if (kind == Kind::prismatic)
      c << k.axis[i], Vec3::Zero();
    else
      c << k.axis[i].cross(e - k.origin[i]), k.axis[i];
    columns.push_back(c);
    stiffness.push_back(table[i].stiffness);
  }
  Vjm v{MatX(6, static_cast<Eigen::Index>(columns.size())),
        VecX(static_cast<Eigen::Index>(columns.size()))};
  for (std::size_t c = 0; c < columns.size(); ++c) {
    v.jacobian.col(static_cast<Eigen::Index>(c)) = columns[c];
    v.stiffness(static_cast<Eigen::Index>(c)) = stiffness[c];
  }
  return v;
}

double relative_difference(const MatX& a, const MatX& b) { return (a - b).norm() / b.norm(); }

// A random six-axis arm: random origins, orientations and axes; the last row a fixed tool.
std::vector<TableJoint> random_arm(std::mt19937& rng, bool with_prismatic) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_real_distribution<double> k(1e5, 1e7);
  const auto random_vec = [&](double scale) -> Vec3 {
    return Vec3(u(rng), u(rng), u(rng)) * scale;
  };
  std::vector<TableJoint> table;
  for (int i = 0; i < 6; ++i) {
    Kind kind = i == 3 ? Kind::continuous : Kind::revolute;
    if (with_prismatic && i == 1) kind = Kind::prismatic;
    table.push_back({"joint_" + std::to_string(i + 1), kind, random_vec(0.4) + Vec3(0, 0, 0.2),
                     random_vec(3.0), random_vec(1.0) + Vec3(0.1, 0, 0), k(rng), 0, Vec3::Zero()});
  }
  table.push_back({"tool_joint", Kind::fixed, Vec3(0.05, 0.02, 0.15), Vec3(0.3, -0.2, 0.1),
                   Vec3::UnitX(), 0, 0, Vec3::Zero()});
  return table;
}

class UrdfRobot : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!STIFFMSA_HAVE_URDF) GTEST_SKIP() << "built without urdfdom";
    folder_ = fs::temp_directory_path() /
              ("stiffmsa_urdf_" +
               std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::create_directories(folder_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(folder_, ignored);
  }
  fs::path write(const std::string& name, const std::string& text) {
    const fs::path path = folder_ / name;
    std::ofstream(path) << text;
    return path;
  }
  fs::path folder_;
};

std::string joints_block(const std::vector<TableJoint>& table) {
  std::ostringstream s;
  s.precision(17);
  s << "  joints:\n";
  for (const auto& j : table)
    if (j.kind != Kind::fixed) s << "    " << j.name << ": {stiffness: " << j.stiffness << "}\n";
  return s.str();
}

std::string positions_block(const std::vector<TableJoint>& table, const std::vector<double>& q) {
  std::ostringstream s;
  s.precision(17);
  s << "  positions: {";
  bool first = true;
  for (std::size_t i = 0; i < table.size(); ++i) {
    if (table[i].kind == Kind::fixed) continue;
    s << (first ? "" : ", ") << table[i].name << ": " << q[i];
    first = false;
  }
  s << "}\n";
  return s.str();
}

TEST_F(UrdfRobot, ComplianceAtRandomAnglesIsTheVirtualJointMethods) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> angle(-2.5, 2.5);
  for (int trial = 0; trial < 8; ++trial) {
    const auto table = random_arm(rng, trial % 2 == 1);
    std::vector<double> q;
    for (std::size_t i = 0; i < table.size(); ++i)
      q.push_back(table[i].kind == Kind::fixed ? 0.0 : angle(rng));
    write("arm.urdf", chain_urdf(table));
    const Vec3 offset(0.01, -0.03, 0.12);
    std::ostringstream yaml;
    yaml.precision(17);
    yaml << "format: stiffmsa/1\nrobot:\n  urdf: arm.urdf\n"
         << positions_block(table, q) << joints_block(table)
         << "end_effectors:\n  flange: {frame: link_6, axes: frame}\n  tool: {frame: link_7, "
            "offset: ["
         << offset.x() << ", " << offset.y() << ", " << offset.z() << "]}\n";
    const Model model = load_model(write("arm.yaml", yaml.str()));
    const Result result = solve(model);
    const ChainFrames k = forward(table, q);
    // The flange's results in its own axes are the world's turned into them.
    ASSERT_TRUE(result.end_effectors[0].in_own_axes);
    Mat6 turn = Mat6::Zero();
    turn.topLeftCorner<3, 3>() = k.rotation[5];
    turn.bottomRightCorner<3, 3>() = k.rotation[5];
    EXPECT_LT((result.end_effectors[0].in_own_axes->axes - k.rotation[5]).norm(), 1e-12);
    EXPECT_LT(relative_difference(*result.end_effectors[0].in_own_axes->compliance,
                                  turn.transpose() * *result.end_effectors[0].compliance * turn),
              1e-12);
    const Vec3 flange = k.origin[5];
    const Vec3 tcp = k.origin[6] + k.rotation[6] * offset;
    for (const auto& [e, point] : {std::pair{0, flange}, std::pair{1, tcp}}) {
      const Vjm v = vjm(table, k, point);
      const MatX expected =
          v.jacobian * v.stiffness.cwiseInverse().asDiagonal() * v.jacobian.transpose();
      ASSERT_TRUE(result.end_effectors[static_cast<std::size_t>(e)].compliance);
      EXPECT_LT(relative_difference(*result.end_effectors[static_cast<std::size_t>(e)].compliance,
                                    expected),
                kExact)
          << "trial " << trial << ", end effector " << e;
    }
  }
}

Mat6 random_spd(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-1, 1);
  Mat6 a;
  for (int i = 0; i < 36; ++i) a.data()[i] = u(rng);
  return scale * (a * a.transpose() + 0.5 * Mat6::Identity());
}

std::string matrix_text(const Mat6& m) {
  std::ostringstream s;
  s.precision(17);
  s << "[";
  for (int r = 0; r < 6; ++r) {
    s << (r ? ", [" : "[");
    for (int c = 0; c < 6; ++c) s << (c ? ", " : "") << m(r, c);
    s << "]";
  }
  s << "]";
  return s.str();
}

TEST_F(UrdfRobot, SixBySixJointCompliancesAddUpTransportedToTheToolFromEachJointFrame) {
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> angle(-2.5, 2.5);
  const auto table = random_arm(rng, false);
  std::vector<double> q;
  for (std::size_t i = 0; i < table.size(); ++i)
    q.push_back(table[i].kind == Kind::fixed ? 0.0 : angle(rng));
  std::vector<Mat6> compliance;
  std::ostringstream yaml;
  yaml << "format: stiffmsa/1\nrobot:\n  urdf: arm.urdf\n"
       << positions_block(table, q) << "  joints:\n";
  for (std::size_t i = 0; i < 6; ++i) {
    compliance.push_back(random_spd(rng, 1e-6));
    yaml << "    " << table[i].name << ": {compliance: " << matrix_text(compliance.back()) << "}\n";
  }
  yaml << "end_effectors:\n  tool: {frame: link_7}\n";
  write("arm.urdf", chain_urdf(table));
  const Result result = solve(load_model(write("arm.yaml", yaml.str())));
  const ChainFrames k = forward(table, q);
  const Vec3 tool = k.origin[6];
  Mat6 expected = Mat6::Zero();
  for (std::size_t i = 0; i < 6; ++i) {
    Mat6 turn = Mat6::Zero();
    turn.topLeftCorner<3, 3>() = k.rotation[i];
    turn.bottomRightCorner<3, 3>() = k.rotation[i];
    const Mat6 to_tool = rigid_transport(tool - k.origin[i]) * turn;
    expected += to_tool * compliance[i] * to_tool.transpose();
  }
  ASSERT_TRUE(result.end_effectors[0].compliance);
  EXPECT_LT(relative_difference(*result.end_effectors[0].compliance, expected), kExact);
}

TEST_F(UrdfRobot, SelfWeightDeflectsTheToolByTheJointTorquesOfTheLinkMasses) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> angle(-2.5, 2.5);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  auto table = random_arm(rng, true);
  for (auto& j : table) {
    j.mass = 5 + 20 * (u(rng) + 0.2);
    j.com = Vec3(u(rng), u(rng), u(rng));
  }
  std::vector<double> q;
  for (std::size_t i = 0; i < table.size(); ++i)
    q.push_back(table[i].kind == Kind::fixed ? 0.0 : angle(rng));
  const Vec3 g(0.3, -0.2, -9.81);
  const Vec6 tool_load = stiffmsa::testing::wrench(100, -50, 200, 5, 0, -8);
  std::ostringstream yaml;
  yaml.precision(17);
  yaml << "format: stiffmsa/1\nrobot:\n  urdf: arm.urdf\n"
       << positions_block(table, q) << joints_block(table) << "  gravity: [" << g.x() << ", "
       << g.y() << ", " << g.z() << "]\n"
       << "end_effectors:\n  tool: {frame: link_7}\nloads:\n  - {frame: link_7, wrench: [100, -50, "
          "200, 5, 0, -8]}\n";
  write("arm.urdf", chain_urdf(table, 1000.0));  // the base's mass goes to the support
  const Result result = solve(load_model(write("arm.yaml", yaml.str())));
  const ChainFrames k = forward(table, q);
  const Vec3 tool = k.origin[6];
  const Vjm v = vjm(table, k, tool);
  // Each movable joint carries the moment (force, for a prismatic one) of every mass beyond it.
  VecX torque = VecX::Zero(v.stiffness.size());
  Eigen::Index column = 0;
  for (std::size_t i = 0; i < table.size(); ++i) {
    if (table[i].kind == Kind::fixed) continue;
    for (std::size_t b = i; b < table.size(); ++b) {
      const Vec3 weight = table[b].mass * g;
      const Vec3 centre = k.origin[b] + k.rotation[b] * table[b].com;
      torque(column) += table[i].kind == Kind::prismatic
                            ? k.axis[i].dot(weight)
                            : k.axis[i].dot((centre - k.origin[i]).cross(weight));
    }
    ++column;
  }
  const Vec6 expected_gravity = v.jacobian * (torque.array() / v.stiffness.array()).matrix();
  const MatX compliance =
      v.jacobian * v.stiffness.cwiseInverse().asDiagonal() * v.jacobian.transpose();
  const Vec6 expected_total = expected_gravity + compliance * tool_load;
  const auto& tool_result = result.end_effectors[0];
  ASSERT_TRUE(tool_result.deflection_gravity);
  ASSERT_TRUE(tool_result.deflection);
  EXPECT_LT((*tool_result.deflection_gravity - expected_gravity).norm(),
            kExact * expected_gravity.norm());
  EXPECT_LT((*tool_result.deflection - expected_total).norm(), kExact * expected_total.norm());
}

// The same arm as plain points, links and joints, from the test's own kinematics; one link a
// tube (whose bending does not depend on how its section is turned).
TEST_F(UrdfRobot, TheSameRobotWrittenByHandGivesTheSameNumbers) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-2.5, 2.5);
  const auto table = random_arm(rng, false);
  std::vector<double> q;
  for (std::size_t i = 0; i < table.size(); ++i)
    q.push_back(table[i].kind == Kind::fixed ? 0.0 : angle(rng));
  const Material steel{2.1e11, 0.3, std::nullopt};
  const Section tube = Section::tube(0.08, 0.006);
  std::ostringstream yaml;
  yaml << "format: stiffmsa/1\nrobot:\n  urdf: arm.urdf\n"
       << positions_block(table, q) << joints_block(table)
       << "  links:\n    link_2: {material: {E: 2.1e11, nu: 0.3}, section: {shape: tube, D: 0.08, "
          "t: 0.006}}\n"
       << "end_effectors:\n  tool: {frame: link_7}\nloads:\n  - {frame: link_7, wrench: [10, 20, "
          "-300, 4, 5, 6]}\n";
  write("arm.urdf", chain_urdf(table));
  const Result from_urdf = solve(load_model(write("arm.yaml", yaml.str())));

  const ChainFrames k = forward(table, q);
  Model hand;
  hand.add_point("p0", Vec3::Zero());
  for (std::size_t i = 0; i < table.size(); ++i)
    hand.add_point("p" + std::to_string(i + 1), k.origin[i]);
  hand.add_point("tip", k.origin[6]);
  for (std::size_t i = 0; i <= table.size(); ++i) {
    const std::string from = "p" + std::to_string(i);
    const std::string to = i == table.size() ? "tip" : "p" + std::to_string(i + 1);
    if (i == 2)
      hand.add_beam("l" + std::to_string(i), from, to, steel, tube);
    else
      hand.add_rigid_link("l" + std::to_string(i), from, to);
  }
  for (std::size_t i = 0; i < table.size(); ++i) {
    Connection c;
    if (table[i].kind != Kind::fixed) {
      c.kinematics = Kinematics::revolute(k.axis[i]);
      c.stiffness = MatX::Constant(1, 1, table[i].stiffness);
    }
    hand.add_joint("j" + std::to_string(i), "p" + std::to_string(i + 1),
                   {"l" + std::to_string(i), "l" + std::to_string(i + 1)}, c);
  }
  hand.add_support("ground", "p0", {}, Connection::rigid());
  hand.add_load("tip", std::nullopt, stiffmsa::testing::wrench(10, 20, -300, 4, 5, 6));
  hand.add_end_effector("tool", "tip");
  const Result by_hand = solve(hand);
  ASSERT_TRUE(from_urdf.end_effectors[0].compliance && by_hand.end_effectors[0].compliance);
  EXPECT_LT(relative_difference(*from_urdf.end_effectors[0].compliance,
                                *by_hand.end_effectors[0].compliance),
            1e-12);
  EXPECT_LT((*from_urdf.end_effectors[0].deflection - *by_hand.end_effectors[0].deflection).norm(),
            1e-12 * by_hand.end_effectors[0].deflection->norm());
}

// Joint positions as expressions of parameters: each member posed by the family's builder is
// the model with those positions written as numbers.
TEST_F(UrdfRobot, JointSpaceMembersAreTheRobotAtThoseAngles) {
  std::mt19937 rng(3);
  const auto table = random_arm(rng, false);
  write("arm.urdf", chain_urdf(table));
  std::ostringstream yaml;
  yaml << "format: stiffmsa/1\nparameters:\n  q2: 0.3\n  q3: {default: 1.1, unit: rad}\nrobot:\n  "
          "urdf: arm.urdf\n"
       << "  positions: {joint_2: q2, joint_3: q3, joint_5: \"q2 - q3\"}\n"
       << joints_block(table) << "end_effectors:\n  tool: {frame: link_7, offset: [0, 0, 0.1]}\n";
  const ModelFamily family = load_model_family(write("arm.yaml", yaml.str()));
  for (const auto& [q2, q3] :
       {std::pair{0.3, 1.1}, std::pair{-1.0, 0.2}, std::pair{0.7, 2.4}, std::pair{-0.2, -0.9}}) {
    const std::vector<double> values{q2, q3};
    const Model member = family.build(values);
    const Result posed = solve(member);
    std::vector<double> q(table.size(), 0.0);
    q[1] = q2;
    q[2] = q3;
    q[4] = q2 - q3;
    std::ostringstream plain;
    plain.precision(17);
    plain << "format: stiffmsa/1\nrobot:\n  urdf: arm.urdf\n"
          << positions_block(table, q) << joints_block(table)
          << "end_effectors:\n  tool: {frame: link_7, offset: [0, 0, 0.1]}\n";
    const Result expected = solve(load_model(write("plain.yaml", plain.str())));
    EXPECT_LT(relative_difference(*posed.end_effectors[0].compliance,
                                  *expected.end_effectors[0].compliance),
              1e-13)
        << "q2 = " << q2 << ", q3 = " << q3;
  }
}

// ---- expand -------------------------------------------------------------------------------

TEST_F(UrdfRobot, TheExpandedModelSolvesToTheSameNumbers) {
  std::mt19937 rng(9);
  auto table = random_arm(rng, true);
  for (auto& j : table) {
    j.mass = 12;
    j.com = Vec3(0.02, -0.01, 0.05);
  }
  write("arm.urdf", chain_urdf(table));
  std::ostringstream yaml;
  yaml << "format: stiffmsa/1\nparameters:\n  q2: 0.3\nrobot:\n  urdf: arm.urdf\n"
       << "  positions: {joint_1: 0.4, joint_2: q2, joint_3: -0.7, joint_5: 1.2}\n"
       << joints_block(table)
       << "  links:\n    link_3: {material: {E: 7e10, nu: 0.33}, section: {shape: rect, b: 0.05, "
          "h: 0.08}}\n"
       << "  gravity: [0, 0, -9.81]\n"
       << "end_effectors:\n  tool: {frame: link_7, offset: [0.01, 0, 0.1]}\n"
       << "loads:\n  - {frame: link_7, offset: [0.01, 0, 0.1], axes: frame, wrench: [0, 0, -100, "
          "0, 0, 3]}\n";
  const ModelFamily family = load_model_family(write("arm.yaml", yaml.str()), {}, {{"q2", -0.4}});
  const Model model = family.build(family.default_values());
  const Result direct = solve(model);
  const Result expanded = solve(parse_model(model_to_yaml(model), "expanded.yaml"));
  ASSERT_TRUE(direct.end_effectors[0].deflection_gravity &&
              expanded.end_effectors[0].deflection_gravity);
  EXPECT_EQ(*direct.end_effectors[0].compliance, *expanded.end_effectors[0].compliance);
  EXPECT_EQ(*direct.end_effectors[0].deflection, *expanded.end_effectors[0].deflection);
  EXPECT_EQ(*direct.end_effectors[0].deflection_gravity,
            *expanded.end_effectors[0].deflection_gravity);
}

// ---- errors ---------------------------------------------------------------------------------

// A defect of the model: its message, where it is and which key.
struct Expected {
  std::string file;  // ends with
  int line;
  std::string key;
  std::string says;
};

void expect_defect(const std::function<void()>& load, const Expected& expected) {
  try {
    load();
    ADD_FAILURE() << "no error; expected: " << expected.says;
  } catch (const InputError& e) {
    bool found = false;
    for (const Diagnostic& d : e.diagnostics())
      found = found ||
              (d.location.file.ends_with(expected.file) && d.location.line == expected.line &&
               d.key_path == expected.key && d.message.find(expected.says) != std::string::npos);
    EXPECT_TRUE(found) << "expected " << expected.file << ":" << expected.line << ": "
                       << expected.key << ": ..." << expected.says << "...\ngot: " << e.what();
  }
}

class UrdfErrors : public UrdfRobot {
 protected:
  void SetUp() override {
    UrdfRobot::SetUp();
    if (IsSkipped()) return;
    std::mt19937 rng(1);
    table_ = random_arm(rng, false);
    write("arm.urdf", chain_urdf(table_));
  }
  // The arm's model file with `extra` lines in its robot block and `rest` after it.
  Model load(const std::string& robot,
             const std::string& rest = "end_effectors:\n  tool: {frame: link_7}\n") {
    return load_model(write("arm.yaml", "format: stiffmsa/1\nrobot:\n" + robot + rest));
  }
  std::vector<TableJoint> table_;
};

TEST_F(UrdfErrors, AMissingUrdfFileIsNamedAtTheUrdfKey) {
  expect_defect([&] { load("  urdf: no-such.urdf\n  default_joint: {stiffness: 1e6}\n"); },
                {"arm.yaml", 3, "robot.urdf",
                 "the URDF file '" + (folder_ / "no-such.urdf").string() + "' does not exist"});
}

TEST_F(UrdfErrors, AJointNotInTheUrdfGetsTheNearestName) {
  expect_defect(
      [&] {
        load(
            "  urdf: arm.urdf\n  default_joint: {stiffness: 1e6}\n  joints:\n    joint_22: "
            "{stiffness: 1e6}\n");
      },
      {"arm.yaml", 6, "robot.joints.joint_22",
       "no joint named 'joint_22' in arm.urdf; did you mean 'joint_2'?"});
  expect_defect(
      [&] {
        load("  urdf: arm.urdf\n  default_joint: {stiffness: 1e6}\n  positions: {jiont_3: 0.5}\n");
      },
      {"arm.yaml", 5, "robot.positions.jiont_3", "did you mean 'joint_3'?"});
}

TEST_F(UrdfErrors, AJointWithoutStiffnessIsAnErrorWithoutADefault) {
  expect_defect([&] { load("  urdf: arm.urdf\n  joints:\n    joint_1: {stiffness: 1e6}\n"); },
                {"arm.yaml", 4, "robot.joints",
                 "the revolute joint 'joint_2' of arm.urdf (line 13) has no stiffness"});
}

TEST_F(UrdfErrors, APositionOutOfItsLimitsIsAWarningWithTheLimits) {
  const Model model =
      load("  urdf: arm.urdf\n  default_joint: {stiffness: 1e6}\n  positions: {joint_2: 3.5}\n");
  ASSERT_EQ(model.warnings.size(), 1u);
  EXPECT_EQ(model.warnings[0].location.line, 5);
  EXPECT_EQ(model.warnings[0].key_path, "robot.positions.joint_2");
  EXPECT_NE(model.warnings[0].message.find("outside its limits [-3, 3] rad"), std::string::npos)
      << model.warnings[0].message;
  const Result result = solve(model);
  ASSERT_FALSE(result.report.warnings.empty());
  EXPECT_NE(result.report.warnings[0].find("joint_2"), std::string::npos);
}

TEST_F(UrdfErrors, AFrameThatDoesNotExistGetsTheNearestName) {
  expect_defect(
      [&] {
        load("  urdf: arm.urdf\n  default_joint: {stiffness: 1e6}\n",
             "end_effectors:\n  tool: {frame: link_8}\n");
      },
      {"arm.yaml", 6, "end_effectors.tool.frame",
       "no frame (URDF link) named 'link_8' in arm.urdf; did you mean"});
  expect_defect(
      [&] { load("  urdf: arm.urdf\n  default_joint: {stiffness: 1e6}\n  base: basse\n"); },
      {"arm.yaml", 5, "robot.base", "no link named 'basse' in arm.urdf; did you mean 'base'?"});
}

TEST_F(UrdfErrors, AnOffsetNeedsAFrameAtTheEndOfTheChain) {
  expect_defect(
      [&] {
        load("  urdf: arm.urdf\n  default_joint: {stiffness: 1e6}\n",
             "end_effectors:\n  tool: {frame: link_3, offset: [0, 0, 1]}\n");
      },
      {"arm.yaml", 6, "end_effectors.tool.frame", "an offset needs a frame at the end of a chain"});
}

TEST_F(UrdfErrors, AJointComplianceMustBeSymmetricPositiveDefinite) {
  Mat6 c = Mat6::Identity() * 1e-6;
  c(2, 2) = -1e-7;
  expect_defect(
      [&] {
        load(
            "  urdf: arm.urdf\n  default_joint: {stiffness: 1e6}\n  joints:\n    joint_1: "
            "{compliance: " +
            matrix_text(c) + "}\n");
      },
      {"arm.yaml", 6, "robot.joints.joint_1.compliance",
       "the compliance is not positive definite"});
  c = Mat6::Identity() * 1e-6;
  c(0, 1) = 1e-8;
  expect_defect(
      [&] {
        load(
            "  urdf: arm.urdf\n  default_joint: {stiffness: 1e6}\n  joints:\n    joint_1: "
            "{compliance: " +
            matrix_text(c) + "}\n");
      },
      {"arm.yaml", 6, "robot.joints.joint_1.compliance", "the compliance is not symmetric"});
}

TEST_F(UrdfErrors, AFlexibleLinkNeedsOneChildJoint) {
  expect_defect(
      [&] {
        load(
            "  urdf: arm.urdf\n  default_joint: {stiffness: 1e6}\n  links:\n    link_7: {material: "
            "{E: 2e11, nu: 0.3}, section: {shape: circle, D: 0.05}}\n");
      },
      {"arm.yaml", 6, "robot.links.link_7",
       "link 'link_7' has 0 child joints: a flexible link runs from its frame's origin"});
}

// The robot's weights come first among the model's loads; a message about the file's own load
// still names it as the file does.
TEST_F(UrdfErrors, ALoadBesideTheWeightsKeepsItsKeyPath) {
  write("heavy.urdf", chain_urdf([&] {
          auto heavy = table_;
          for (auto& j : heavy) j.mass = 2;
          return heavy;
        }()));
  expect_defect(
      [&] {
        load_model(write(
            "arm.yaml",
            "format: stiffmsa/1\nrobot:\n  urdf: heavy.urdf\n  default_joint: {stiffness: 1e6}\n"
            "  gravity: [0, 0, -9.81]\nloads:\n  - {at: nowhere, wrench: [1, 0, 0, 0, 0, 0]}\n"));
      },
      {"arm.yaml", 7, "loads[0].at", "no point named 'nowhere'"});
}

// The URDF's own defects are told at their line in the URDF.
TEST_F(UrdfErrors, UrdfJointsStiffmsaCannotModelAreNamedAtTheirLine) {
  const std::string robot = "  urdf: bad.urdf\n  default_joint: {stiffness: 1e6}\n";
  const std::string head =
      "<?xml version=\"1.0\"?>\n<robot name=\"r\">\n  <link name=\"a\"/>\n  <link name=\"b\"/>\n  "
      "<link name=\"c\"/>\n";
  write("bad.urdf", head +
                        "  <joint name=\"free\" type=\"floating\"><parent link=\"a\"/><child "
                        "link=\"b\"/></joint>\n"
                        "  <joint name=\"j2\" type=\"fixed\"><parent link=\"b\"/><child "
                        "link=\"c\"/></joint>\n</robot>\n");
  expect_defect([&] { load(robot, ""); },
                {"bad.urdf", 6, "robot.urdf", "joint 'free' is floating"});
  write("bad.urdf",
        head +
            "  <joint name=\"j1\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>"
            "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n"
            "  <joint name=\"j2\" type=\"revolute\"><parent link=\"b\"/><child link=\"c\"/><mimic "
            "joint=\"j1\"/>"
            "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n</robot>\n");
  expect_defect([&] { load(robot, ""); },
                {"bad.urdf", 7, "robot.urdf", "joint 'j2' mimics another joint"});
  write("bad.urdf",
        head +
            "  <joint name=\"j1\" type=\"fixed\"><parent link=\"a\"/><child link=\"c\"/></joint>\n"
            "  <joint name=\"j2\" type=\"fixed\"><parent link=\"b\"/><child "
            "link=\"c\"/></joint>\n</robot>\n");
  expect_defect(
      [&] { load(robot, ""); },
      {"bad.urdf", 7, "robot.urdf", "the URDF is not a tree: link 'c' is the child of joint 'j1'"});
  write("bad.urdf", head +
                        "  <joint name=\"j1\" type=\"fixed\"><parent link=\"a\"/><child "
                        "link=\"d\"/></joint>\n</robot>\n");
  expect_defect([&] { load(robot, ""); },
                {"bad.urdf", 6, "robot.urdf", "its child link 'd' is not in the URDF"});
  write("bad.urdf", head + "  <joint name=\"j1\" type=\"fixed\"><parent link=\"a\"/>\n</robot>\n");
  expect_defect([&] { load(robot, ""); },
                {"bad.urdf", 7, "robot.urdf", "the URDF is not well-formed XML"});
  write("bad.urdf", head +
                        "  <joint name=\"j1\" type=\"continuous\"><parent link=\"a\"/><child "
                        "link=\"b\"/><axis xyz=\"0 0 0\"/></joint>\n"
                        "  <joint name=\"j2\" type=\"fixed\"><parent link=\"b\"/><child "
                        "link=\"c\"/></joint>\n</robot>\n");
  expect_defect([&] { load(robot, ""); }, {"bad.urdf", 6, "robot.urdf", "axis is a zero vector"});
  write(
      "bad.urdf",
      head +
          "  <joint name=\"j1\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/></joint>\n"
          "  <joint name=\"j2\" type=\"fixed\"><parent link=\"b\"/><child "
          "link=\"c\"/></joint>\n</robot>\n");
  // urdfdom's own check, placed at the joint it names.
  expect_defect([&] { load(robot, ""); }, {"bad.urdf", 6, "robot.urdf", "urdfdom: "});
}

// ---- the examples -----------------------------------------------------------------------------

Result solve_robot_example(const std::string& file) {
  return solve(load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/robots/" + file));
}

// The six-axis example's tool centre point lies beyond tool0, fixed at the chain's end: the link
// that ends at tool0 runs on to it, so the robot has the seven links of the hand-written 6-axis
// example; an end effector at tool0 itself keeps tool0 a link end and the tool link apart. The
// numbers at the tool centre point are the same either way.
TEST_F(UrdfRobot, AToolCentrePointExtendsTheLinkThatEndsAtItsFrame) {
  const fs::path examples = fs::path(STIFFMSA_SOURCE_DIR) / "examples" / "robots";
  const Model folded = load_model(examples / "six-axis.yaml");
  EXPECT_EQ(folded.links.size(), 7u);
  EXPECT_EQ(folded.find_link("tcp.tcp"), nullptr);
  ASSERT_NE(folded.find_link("link_6"), nullptr);
  EXPECT_EQ(folded.find_link("link_6")->to, "tcp.tcp");
  EXPECT_EQ(folded.end_effectors.at(0).link, "link_6");
  EXPECT_NE(folded.find_point("tool0"), nullptr);

  fs::copy_file(examples / "six-axis.urdf", folder_ / "six-axis.urdf");
  std::ostringstream text;
  text << std::ifstream(examples / "six-axis.yaml").rdbuf();
  std::string yaml = text.str();
  const std::string tcp = "  tcp: {frame: tool0, offset: [0, 0, 0.15]}\n";
  ASSERT_NE(yaml.find(tcp), std::string::npos);
  yaml.replace(yaml.find(tcp), tcp.size(), tcp + "  flange: {frame: tool0}\n");
  const Model apart = load_model(write("six-axis.yaml", yaml));
  EXPECT_EQ(apart.links.size(), 8u);
  ASSERT_NE(apart.find_link("tcp.tcp"), nullptr);
  EXPECT_EQ(apart.find_link("link_6")->to, "tool0");

  const Result a = solve(folded), b = solve(apart);
  ASSERT_TRUE(a.end_effectors.at(0).compliance && b.end_effectors.at(0).compliance);
  EXPECT_LT(relative_difference(*a.end_effectors[0].compliance, *b.end_effectors[0].compliance),
            1e-12);
  EXPECT_LT(relative_difference(*a.end_effectors[0].deflection, *b.end_effectors[0].deflection),
            1e-12);
}

TEST_F(UrdfRobot, TheRobotExamplesSolveCleanly) {
  for (const char* file : {"six-axis.yaml", "seven-axis.yaml", "tripod.yaml"}) {
    const Result result = solve_robot_example(file);
    EXPECT_TRUE(result.report.warnings.empty()) << file;
    EXPECT_LT(result.report.relative_residual, 1e-12) << file;
    EXPECT_LT(result.report.equilibrium_error, 1e-12) << file;
    ASSERT_TRUE(result.end_effectors.at(0).stiffness) << file;
  }
}

// The seven-axis arm's payload acts at its end effector in world axes: what it adds to the
// weight's deflection is the compliance times it.
TEST_F(UrdfRobot, TheSevenAxisArmsPayloadAddsItsComplianceTimesTheLoadToTheSag) {
  const Result result = solve_robot_example("seven-axis.yaml");
  const auto& tcp = result.end_effectors.at(0);
  ASSERT_TRUE(tcp.deflection && tcp.deflection_gravity && tcp.compliance);
  const Vec6 payload = stiffmsa::testing::wrench(0, 0, -49.05, 0, 0, 0);
  const Vec6 expected = *tcp.deflection_gravity + *tcp.compliance * payload;
  EXPECT_LT((*tcp.deflection - expected).norm(), 1e-10 * tcp.deflection->norm());
  EXPECT_GT(tcp.deflection_gravity->head<3>().norm(), 1e-5);  // the sag is the larger part here
}

// Where an expression of the robot block goes through forward kinematics (gravity times the
// masses here), each member is read afresh: still the robot at those values.
TEST_F(UrdfRobot, AnExpressionForwardKinematicsTransformsStillGivesEachMember) {
  std::mt19937 rng(12);
  auto table = random_arm(rng, false);
  for (auto& j : table) j.mass = 3;
  write("arm.urdf", chain_urdf(table));
  std::ostringstream yaml;
  yaml << "format: stiffmsa/1\nparameters:\n  g: 9.81\n  q2: 0.5\nrobot:\n  urdf: arm.urdf\n"
       << "  positions: {joint_2: q2}\n"
       << joints_block(table) << "  gravity: [0, 0, -g]\n"
       << "end_effectors:\n  tool: {frame: link_7}\n";
  const ModelFamily family = load_model_family(write("arm.yaml", yaml.str()));
  const Vec6 earth =
      *solve(family.build(std::vector<double>{9.81, 0.5})).end_effectors[0].deflection_gravity;
  const Vec6 moon =
      *solve(family.build(std::vector<double>{1.62, 0.5})).end_effectors[0].deflection_gravity;
  EXPECT_LT((moon - earth * (1.62 / 9.81)).norm(), 1e-12 * moon.norm());
}

TEST_F(UrdfRobot, TheExpandCommandWritesAModelThatSolvesToTheSameNumbers) {
  const std::string robot = std::string(STIFFMSA_SOURCE_DIR) + "/examples/robots/six-axis.yaml";
  const fs::path out = folder_ / "expanded.yaml";
  const std::string command =
      std::string(STIFFMSA_CLI) + " expand " + robot + " --set q3=-0.5 -o " + out.string();
  ASSERT_EQ(std::system(command.c_str()), 0);
  const ModelFamily family = load_model_family(robot, {}, {{"q3", -0.5}});
  const Result direct = solve(family.build(family.default_values()));
  const Result expanded = solve(load_model(out));
  EXPECT_EQ(*direct.end_effectors[0].compliance, *expanded.end_effectors[0].compliance);
  EXPECT_EQ(*direct.end_effectors[0].deflection, *expanded.end_effectors[0].deflection);
  // The expanded model is the robot's, not the file's own text again.
  std::ifstream text(out);
  const std::string written((std::istreambuf_iterator<char>(text)),
                            std::istreambuf_iterator<char>());
  EXPECT_EQ(written.find("robot:"), std::string::npos);
  EXPECT_NE(written.find("\"joint_3\": {type: revolute"), std::string::npos);
}

}  // namespace
}  // namespace stiffmsa
