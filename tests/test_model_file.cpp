// Reading valid model files (model-format.md): every key lands in the right Model value.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "stiffmsa/io/model_file.hpp"
#include "stiffmsa/structure.hpp"

namespace stiffmsa {
namespace {

// Parses `text`, failing the test with every diagnostic if the model is rejected.
Model parse(const std::string& text, const std::string& file = "test.yaml") {
  try {
    return parse_model(text, file);
  } catch (const InputError& e) {
    ADD_FAILURE() << e.what();
    return {};
  }
}

const Link& link_named(const Model& m, const std::string& name) {
  const Link* link = m.find_link(name);
  EXPECT_NE(link, nullptr) << name;
  return *link;
}

const Joint& joint_named(const Model& m, const std::string& name) {
  for (const auto& j : m.joints)
    if (j.name == name) return j;
  ADD_FAILURE() << "no joint " << name;
  return m.joints.front();
}

// The example of model-format.md, word for word.
const char* const kSpecExample = R"(format: stiffmsa/1
name: planar-2R-example

materials:                         # optional, referenced by name
  steel: {E: 2.1e11, nu: 0.3}      # give exactly one of nu or G with E

sections:                          # optional, referenced by name
  arm:  {shape: tube, D: 0.08, t: 0.005}     # circle{D}, tube{D, t}, rect{b, h}, rect_tube{b, h, t}
  rod:  {A: 1.0e-3, Iy: 1.0e-7, Iz: 2.0e-7, J: 2.5e-7}   # generic; optional Asy, Asz for shear

points:
  O: [0, 0, 0]
  A: [0.5, 0, 0]
  E: [1.0, 0, 0]

links:
  L1: {type: beam, from: O, to: A, material: steel, section: arm}   # flexible link
  L2: {type: rigid, from: A, to: E}                                 # rigid link

joints:
  J1: {type: revolute, at: A, links: [L1, L2], axis: [0, 0, 1]}            # passive

supports:
  S1: {type: rigid, at: O, link: L1}

loads:
  - {at: E, link: L2, wrench: [0, -100, 0, 0, 0, 0]}   # `link` may be left out where one end is at the point

end_effectors:
  EE: {at: E, link: L2}            # `link` may be left out where one end is at the point
)";

TEST(ModelFile, ReadsTheSpecificationExample) {
  const Model m = parse(kSpecExample, "models/planar.yaml");
  EXPECT_EQ(m.name, "planar-2R-example");
  EXPECT_EQ(m.source_file, "models/planar.yaml");

  ASSERT_EQ(m.points.size(), 3u);
  EXPECT_EQ(m.points[1].name, "A");
  EXPECT_EQ(m.points[1].position, Vec3(0.5, 0, 0));
  EXPECT_EQ(m.points[2].position, Vec3(1.0, 0, 0));

  ASSERT_EQ(m.links.size(), 2u);
  const Link& l1 = link_named(m, "L1");
  EXPECT_EQ(l1.from, "O");
  EXPECT_EQ(l1.to, "A");
  const auto& beam = std::get<BeamLink>(l1.kind);
  EXPECT_EQ(beam.material.E, 2.1e11);
  EXPECT_EQ(beam.material.nu, 0.3);
  EXPECT_FALSE(beam.material.G.has_value());
  EXPECT_EQ(beam.section.shape, SectionShape::tube);
  EXPECT_EQ(beam.section.D, 0.08);
  EXPECT_EQ(beam.section.t, 0.005);
  EXPECT_FALSE(beam.shear);
  EXPECT_FALSE(beam.zref.has_value());
  EXPECT_TRUE(std::holds_alternative<RigidLink>(link_named(m, "L2").kind));

  ASSERT_EQ(m.joints.size(), 1u);
  const Joint& j1 = m.joints[0];
  EXPECT_EQ(j1.name, "J1");
  EXPECT_EQ(j1.at, "A");
  EXPECT_EQ(j1.links, (std::vector<std::string>{"L1", "L2"}));
  EXPECT_EQ(j1.connection.kinematics.type, JointType::revolute);
  EXPECT_EQ(j1.connection.kinematics.axis, Vec3(0, 0, 1));
  EXPECT_FALSE(j1.connection.stiffness.has_value());
  EXPECT_FALSE(j1.connection.preload.has_value());
  EXPECT_FALSE(j1.connection.is_actuated);

  ASSERT_EQ(m.supports.size(), 1u);
  EXPECT_EQ(m.supports[0].name, "S1");
  EXPECT_EQ(m.supports[0].at, "O");
  EXPECT_EQ(m.supports[0].links, std::vector<std::string>{"L1"});
  EXPECT_EQ(m.supports[0].connection.kinematics.type, JointType::rigid);

  ASSERT_EQ(m.loads.size(), 1u);
  EXPECT_EQ(m.loads[0].at, "E");
  EXPECT_EQ(m.loads[0].link, "L2");
  Vec6 wrench;
  wrench << 0, -100, 0, 0, 0, 0;
  EXPECT_EQ(m.loads[0].wrench, wrench);

  ASSERT_EQ(m.end_effectors.size(), 1u);
  EXPECT_EQ(m.end_effectors[0].name, "EE");
  EXPECT_EQ(m.end_effectors[0].at, "E");
  EXPECT_EQ(m.end_effectors[0].link, "L2");
}

TEST(ModelFile, RecordsWhereEachEntityAndKeyIs) {
  const Model m = parse(kSpecExample, "planar.yaml");
  const Joint& j1 = m.joints[0];
  // Line 21: "  J1: {type: revolute, at: A, links: [L1, L2], axis: [0, 0, 1]}"
  EXPECT_EQ(j1.origin.location.file, "planar.yaml");
  EXPECT_EQ(j1.origin.location.line, 21);
  EXPECT_EQ(j1.origin.location.column, 3);
  EXPECT_EQ(j1.origin.of("axis").line, 21);
  EXPECT_EQ(j1.origin.of("axis").column, 48);
  EXPECT_EQ(j1.origin.of("links[1]").column, 43);
  // A named material's keys point at its definition (line 5), not at the beam.
  const Link& l1 = link_named(m, "L1");
  EXPECT_EQ(l1.origin.location.line, 17);
  EXPECT_EQ(l1.origin.of("material").line, 17);
  EXPECT_EQ(l1.origin.of("material.E").line, 5);
  EXPECT_EQ(l1.origin.of("material.E").column, 11);
  EXPECT_EQ(l1.origin.of("section.t").line, 8);
  EXPECT_EQ(m.loads[0].origin.location.line, 27);
  EXPECT_EQ(m.loads[0].origin.of("wrench").column, 23);
}

TEST(ModelFile, NameDefaultsToTheFileNameWithoutExtension) {
  const std::string text = R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0]}
links: {L: {type: rigid, from: O, to: A}}
)";
  EXPECT_EQ(parse(text, "robots/delta-arm.yaml").name, "delta-arm");
  EXPECT_EQ(parse(text, "robots/delta-arm.yaml").source_file, "robots/delta-arm.yaml");
  EXPECT_EQ(parse(text, "cell.v2.json").name, "cell.v2");
}

TEST(ModelFile, AcceptsJson) {
  const std::string text = R"({
  "format": "stiffmsa/1",
  "name": "json-model",
  "materials": {"alu": {"E": 7.0e10, "G": 2.6e10}},
  "points": {"O": [0, 0, 0], "A": [0, 0.25, 0]},
  "links": {"L": {"type": "beam", "from": "O", "to": "A", "material": "alu",
                  "section": {"shape": "circle", "D": 0.02}, "shear": true}},
  "supports": {"S": {"type": "rigid", "at": "O"}},
  "loads": [{"at": "A", "wrench": [1, 2, 3, 4, 5, 6]}],
  "end_effectors": {"tip": {"at": "A"}}
})";
  const Model m = parse(text, "model.json");
  EXPECT_EQ(m.name, "json-model");
  EXPECT_EQ(m.points[1].position, Vec3(0, 0.25, 0));
  const auto& beam = std::get<BeamLink>(m.links[0].kind);
  EXPECT_EQ(beam.material.E, 7.0e10);
  EXPECT_EQ(beam.material.G, 2.6e10);
  EXPECT_FALSE(beam.material.nu.has_value());
  EXPECT_EQ(beam.section.shape, SectionShape::circle);
  EXPECT_EQ(beam.section.D, 0.02);
  EXPECT_TRUE(beam.shear);
  EXPECT_TRUE(m.supports[0].links.empty());
  EXPECT_FALSE(m.loads[0].link.has_value());
  EXPECT_EQ(m.loads[0].wrench(5), 6.0);
  EXPECT_FALSE(m.end_effectors[0].link.has_value());
}

TEST(ModelFile, ReadsEverySectionShape) {
  const std::string text = R"(format: stiffmsa/1
sections:
  c:  {shape: circle, D: 0.03}
  t:  {shape: tube, D: 0.08, t: 0.004}
  r:  {shape: rect, b: 0.1, h: 0.2, Asy: 0.015}
  rt: {shape: rect_tube, b: 0.1, h: 0.06, t: 0.005}
  g:  {A: 1.0e-3, Iy: 1.0e-7, Iz: 2.0e-7, J: 2.5e-7, Asy: 8.0e-4, Asz: 7.0e-4}
  g2: {shape: generic, A: 2.0e-3, Iy: 3.0e-7, Iz: 4.0e-7, J: 5.0e-7}
materials: {steel: {E: 2.1e11, nu: 0.3}}
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0], C: [3, 0, 0], D: [4, 0, 0], E: [5, 0, 0], F: [6, 0, 0]}
links:
  Lc:  {type: beam, from: O, to: A, material: steel, section: c}
  Lt:  {type: beam, from: A, to: B, material: steel, section: t}
  Lr:  {type: beam, from: B, to: C, material: steel, section: r}
  Lrt: {type: beam, from: C, to: D, material: steel, section: rt}
  Lg:  {type: beam, from: D, to: E, material: steel, section: g, shear: true}
  Lg2: {type: beam, from: E, to: F, material: steel, section: g2}
)";
  const Model m = parse(text);
  const auto section = [&](const char* link) {
    return std::get<BeamLink>(link_named(m, link).kind).section;
  };
  EXPECT_EQ(section("Lc").shape, SectionShape::circle);
  EXPECT_EQ(section("Lc").D, 0.03);
  EXPECT_EQ(section("Lt").shape, SectionShape::tube);
  EXPECT_EQ(section("Lt").t, 0.004);
  EXPECT_EQ(section("Lr").shape, SectionShape::rect);
  EXPECT_EQ(section("Lr").b, 0.1);
  EXPECT_EQ(section("Lr").h, 0.2);
  EXPECT_EQ(section("Lr").Asy, 0.015);
  EXPECT_FALSE(section("Lr").Asz.has_value());
  EXPECT_EQ(section("Lrt").shape, SectionShape::rect_tube);
  EXPECT_EQ(section("Lrt").h, 0.06);
  EXPECT_EQ(section("Lrt").t, 0.005);
  EXPECT_EQ(section("Lg").shape, SectionShape::generic);
  EXPECT_EQ(section("Lg").A, 1.0e-3);
  EXPECT_EQ(section("Lg").Iy, 1.0e-7);
  EXPECT_EQ(section("Lg").Iz, 2.0e-7);
  EXPECT_EQ(section("Lg").J, 2.5e-7);
  EXPECT_EQ(section("Lg").Asy, 8.0e-4);
  EXPECT_EQ(section("Lg").Asz, 7.0e-4);
  EXPECT_EQ(section("Lg2").shape, SectionShape::generic);
  EXPECT_EQ(section("Lg2").J, 5.0e-7);
}

// A 12×12 free-free matrix: an axial spring k between the two ends along x.
std::string axial_spring_yaml(double k) {
  std::ostringstream out;
  out << "[";
  for (int i = 0; i < 12; ++i) {
    out << (i ? ", " : "") << "[";
    for (int j = 0; j < 12; ++j) {
      const double v = (i % 6 == 0 && j % 6 == 0) ? (i == j ? k : -k) : 0.0;
      out << (j ? ", " : "") << v;
    }
    out << "]";
  }
  out << "]";
  return out.str();
}

TEST(ModelFile, ReadsEveryLinkType) {
  const std::string text = R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0], C: [2, 0, 0], D: [2, 1, 0]}
links:
  beam: {type: beam, from: O, to: A, material: {E: 7.0e10, G: 2.7e10},
         section: {shape: rect, b: 0.02, h: 0.04}, shear: true, zref: [0, 1, 1]}
  K:    {type: matrix, from: A, to: B, K: )" +
                           axial_spring_yaml(2.0e6) + R"(, frame: local, zref: [0, 0, 1]}
  bushing: {type: compliance, from: B, to: C, C: [[1e-6, 0, 0, 0, 0, 0], [0, 2e-6, 0, 0, 0, 0],
            [0, 0, 3e-6, 0, 0, 0], [0, 0, 0, 4e-5, 0, 0], [0, 0, 0, 0, 5e-5, 0], [0, 0, 0, 0, 0, 6e-5]]}
  arm:  {type: compliance, from: C, to: D, frame: local,
         C: [[1e-6, 0, 0, 0, 0, 0], [0, 1e-6, 0, 0, 0, 0], [0, 0, 1e-6, 0, 0, 0],
             [0, 0, 0, 1e-5, 0, 0], [0, 0, 0, 0, 1e-5, 0], [0, 0, 0, 0, 0, 1e-5]]}
)";
  const Model m = parse(text);
  const auto& beam = std::get<BeamLink>(link_named(m, "beam").kind);
  EXPECT_EQ(beam.material.E, 7.0e10);
  EXPECT_EQ(beam.material.G, 2.7e10);
  EXPECT_EQ(beam.section.shape, SectionShape::rect);
  EXPECT_EQ(beam.section.h, 0.04);
  EXPECT_TRUE(beam.shear);
  EXPECT_EQ(beam.zref, Vec3(0, 1, 1));

  const auto& matrix = std::get<MatrixLink>(link_named(m, "K").kind);
  EXPECT_EQ(matrix.frame, LinkFrame::local);
  EXPECT_EQ(matrix.zref, Vec3(0, 0, 1));
  EXPECT_EQ(matrix.K(0, 0), 2.0e6);
  EXPECT_EQ(matrix.K(0, 6), -2.0e6);
  EXPECT_EQ(matrix.K(6, 6), 2.0e6);
  EXPECT_EQ(matrix.K(1, 1), 0.0);

  const auto& bushing = std::get<ComplianceLink>(link_named(m, "bushing").kind);
  EXPECT_EQ(bushing.frame, LinkFrame::global);
  EXPECT_EQ(bushing.C(2, 2), 3e-6);
  EXPECT_EQ(bushing.C(5, 5), 6e-5);
  EXPECT_EQ(bushing.C(0, 1), 0.0);
  EXPECT_EQ(std::get<ComplianceLink>(link_named(m, "arm").kind).frame, LinkFrame::local);
}

// A chain O-A-B-...: one joint per inner point, so every elastic joint joins two link ends.
std::string chain(const std::string& joints) {
  return R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0], C: [3, 0, 0], D: [4, 0, 0], E: [5, 0, 0],
         F: [6, 0, 0], G: [7, 0, 0], H: [8, 0, 0], I: [9, 0, 0]}
links:
  L1: {type: rigid, from: O, to: A}
  L2: {type: rigid, from: A, to: B}
  L3: {type: rigid, from: B, to: C}
  L4: {type: rigid, from: C, to: D}
  L5: {type: rigid, from: D, to: E}
  L6: {type: rigid, from: E, to: F}
  L7: {type: rigid, from: F, to: G}
  L8: {type: rigid, from: G, to: H}
  L9: {type: rigid, from: H, to: I}
joints:
)" + joints;
}

TEST(ModelFile, ReadsEveryJointType) {
  const Model m = parse(chain(R"(
  Jr: {type: rigid, at: A, links: [L1, L2]}
  Jv: {type: revolute, at: B, links: [L2, L3], axis: [0, 0, 2]}
  Jp: {type: prismatic, at: C, links: [L3, L4], axis: [1, 0, 0]}
  Jc: {type: cylindrical, at: D, links: [L4, L5], axis: [0, 1, 0]}
  Ju: {type: universal, at: E, links: [L5, L6], axes: [[1, 0, 0], [0, 1, 0]]}
  Js: {type: spherical, at: F, links: [L6, L7]}
  Jl: {type: planar, at: G, links: [L7, L8], normal: [0, 0, 1]}
  Jx: {type: custom, at: H, links: [L8, L9], free: [[0, 0, 0, 0, 0, 1], [1, 0, 0, 0, 0, 0.5]]}
)"));
  EXPECT_EQ(joint_named(m, "Jr").connection.kinematics.type, JointType::rigid);
  const Kinematics& revolute = joint_named(m, "Jv").connection.kinematics;
  EXPECT_EQ(revolute.type, JointType::revolute);
  EXPECT_EQ(revolute.axis, Vec3(0, 0, 2));  // not normalised in the model
  EXPECT_EQ(joint_named(m, "Jp").connection.kinematics.type, JointType::prismatic);
  EXPECT_EQ(joint_named(m, "Jp").connection.kinematics.axis, Vec3(1, 0, 0));
  EXPECT_EQ(joint_named(m, "Jc").connection.kinematics.type, JointType::cylindrical);
  EXPECT_EQ(joint_named(m, "Jc").connection.kinematics.axis, Vec3(0, 1, 0));
  const Kinematics& universal = joint_named(m, "Ju").connection.kinematics;
  EXPECT_EQ(universal.type, JointType::universal);
  EXPECT_EQ(universal.axis, Vec3(1, 0, 0));
  EXPECT_EQ(universal.axis_b, Vec3(0, 1, 0));
  EXPECT_EQ(joint_named(m, "Js").connection.kinematics.type, JointType::spherical);
  EXPECT_EQ(joint_named(m, "Jl").connection.kinematics.type, JointType::planar);
  EXPECT_EQ(joint_named(m, "Jl").connection.kinematics.normal, Vec3(0, 0, 1));
  const Kinematics& custom = joint_named(m, "Jx").connection.kinematics;
  EXPECT_EQ(custom.type, JointType::custom);
  ASSERT_EQ(custom.free_rows.size(), 2u);
  Vec6 second;
  second << 1, 0, 0, 0, 0, 0.5;
  EXPECT_EQ(custom.free_rows[1], second);
  EXPECT_EQ(free_direction_count(custom), 2);
}

TEST(ModelFile, NormalisesStiffnessAndPreload) {
  const Model m = parse(chain(R"(
  scalar:   {type: cylindrical, at: A, links: [L1, L2], axis: [0, 0, 1], stiffness: 500}
  diagonal: {type: spherical, at: B, links: [L2, L3], stiffness: [10, 20, 30], preload: [1, 2, 3]}
  full:     {type: universal, at: C, links: [L3, L4], axes: [[1, 0, 0], [0, 1, 0]],
             stiffness: [[4, 1], [1, 3]], preload: [0.5, -0.5]}
  one:      {type: revolute, at: D, links: [L4, L5], axis: [0, 0, 1], stiffness: 7, preload: 2.5,
             actuated: true}
  one_list: {type: prismatic, at: E, links: [L5, L6], axis: [1, 0, 0], stiffness: [8], preload: [-1]}
  passive:  {type: revolute, at: F, links: [L6, L7], axis: [0, 0, 1], preload: 4}
  locked:   {type: revolute, at: G, links: [L7, L8], axis: [0, 0, 1], actuated: true}
  custom:   {type: custom, at: H, links: [L8, L9], free: [[0, 0, 1, 0, 0, 0]], stiffness: 9}
)"));
  EXPECT_EQ(*joint_named(m, "scalar").connection.stiffness, MatX(500 * MatX::Identity(2, 2)));

  MatX diagonal = MatX::Zero(3, 3);
  diagonal.diagonal() << 10, 20, 30;
  EXPECT_EQ(*joint_named(m, "diagonal").connection.stiffness, diagonal);
  EXPECT_EQ(*joint_named(m, "diagonal").connection.preload, Eigen::Vector3d(1, 2, 3));

  MatX full(2, 2);
  full << 4, 1, 1, 3;
  EXPECT_EQ(*joint_named(m, "full").connection.stiffness, full);
  EXPECT_EQ(*joint_named(m, "full").connection.preload, Eigen::Vector2d(0.5, -0.5));

  const Connection& one = joint_named(m, "one").connection;
  EXPECT_EQ(*one.stiffness, MatX::Constant(1, 1, 7));
  EXPECT_EQ(*one.preload, VecX::Constant(1, 2.5));
  EXPECT_TRUE(one.is_actuated);

  EXPECT_EQ(*joint_named(m, "one_list").connection.stiffness, MatX::Constant(1, 1, 8));
  EXPECT_EQ(*joint_named(m, "one_list").connection.preload, VecX::Constant(1, -1));

  const Connection& passive = joint_named(m, "passive").connection;
  EXPECT_FALSE(passive.stiffness.has_value());
  EXPECT_EQ(*passive.preload, VecX::Constant(1, 4));
  EXPECT_FALSE(passive.is_actuated);

  const Connection& locked = joint_named(m, "locked").connection;
  EXPECT_TRUE(locked.is_actuated);
  EXPECT_FALSE(locked.stiffness.has_value());

  EXPECT_EQ(*joint_named(m, "custom").connection.stiffness, MatX::Constant(1, 1, 9));
}

TEST(ModelFile, ReadsSupportsWithOneSeveralOrAllLinks) {
  const std::string text = R"(format: stiffmsa/1
points: {O: [0, 0, 0], P: [0, 1, 0], Q: [0, 2, 0], A: [1, 0, 0], B: [1, 1, 0], C: [1, 2, 0]}
links:
  L1: {type: rigid, from: O, to: A}
  L2: {type: rigid, from: P, to: B}
  L3: {type: rigid, from: P, to: C}
  L4: {type: rigid, from: Q, to: C}
  L5: {type: rigid, from: Q, to: A}
supports:
  one:     {type: revolute, at: O, link: L1, axis: [0, 0, 1], stiffness: 1.0e4}
  several: {type: spherical, at: P, links: [L2, L3], stiffness: 2.0e3, actuated: true}
  all:     {type: planar, at: Q, normal: [0, 0, 1], preload: [0, 0, 1.5]}
)";
  const Model m = parse(text);
  ASSERT_EQ(m.supports.size(), 3u);
  EXPECT_EQ(m.supports[0].links, std::vector<std::string>{"L1"});
  EXPECT_EQ(m.supports[0].connection.kinematics.type, JointType::revolute);
  EXPECT_EQ(*m.supports[0].connection.stiffness, MatX::Constant(1, 1, 1.0e4));
  EXPECT_EQ(m.supports[1].links, (std::vector<std::string>{"L2", "L3"}));
  EXPECT_EQ(*m.supports[1].connection.stiffness, MatX(2.0e3 * MatX::Identity(3, 3)));
  EXPECT_TRUE(m.supports[1].connection.is_actuated);
  EXPECT_TRUE(m.supports[2].links.empty());
  EXPECT_EQ(m.supports[2].connection.kinematics.normal, Vec3(0, 0, 1));
  EXPECT_EQ(*m.supports[2].connection.preload, Eigen::Vector3d(0, 0, 1.5));
}

TEST(ModelFile, IgnoresXKeysWhereTheFormatFixesTheKeys) {
  const std::string text = R"(format: stiffmsa/1
x-author: someone
x-notes: {revision: 3}
materials: {steel: {E: 2.1e11, nu: 0.3, x-grade: S355}}
points: {x-1: [0, 0, 0], A: [1, 0, 0]}
links:
  L: {type: beam, from: x-1, to: A, material: steel,
      section: {shape: circle, D: 0.02, x-source: catalogue}, x-colour: red}
supports:
  S: {type: rigid, at: x-1, x-comment: bolted}
loads:
  - {at: A, wrench: [0, 0, -10, 0, 0, 0], x-case: gravity}
end_effectors:
  tool: {at: A, x-tcp: true}
)";
  const Model m = parse(text);
  // In points, `x-1` is a name the user chose, not a note.
  ASSERT_EQ(m.points.size(), 2u);
  EXPECT_EQ(m.points[0].name, "x-1");
  EXPECT_EQ(m.links[0].from, "x-1");
  EXPECT_EQ(std::get<BeamLink>(m.links[0].kind).material.E, 2.1e11);
  EXPECT_EQ(std::get<BeamLink>(m.links[0].kind).section.D, 0.02);
  EXPECT_EQ(m.supports[0].at, "x-1");
  EXPECT_EQ(m.loads[0].wrench(2), -10.0);
  EXPECT_EQ(m.end_effectors[0].at, "A");
  EXPECT_EQ(m.links[0].origin.find("x-colour"), nullptr);
}

TEST(ModelFile, ReadsNumbersInEveryYamlSpelling) {
  const std::string text = R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [+1.5, -2, 3e-1], B: [1E2, 0.0, -0.]}
links: {L: {type: rigid, from: O, to: A}, M: {type: rigid, from: A, to: B}}
)";
  const Model m = parse(text);
  EXPECT_EQ(m.points[1].position, Vec3(1.5, -2, 0.3));
  EXPECT_EQ(m.points[2].position, Vec3(100, 0, 0));
}

// Issue 22's keys: loads along links beside point loads, gravity, densities, load cases,
// settlements and the analysis mode.
const char* const kLoadedFrame = R"(format: stiffmsa/1
analysis: {mode: loaded, load_steps: 12}
gravity: [0, 0, -9.81]
materials: {steel: {E: 2.1e11, nu: 0.3, density: 7850}}
sections: {rod: {shape: circle, D: 0.05}}
points: {O: [0, 0, 0], A: [1, 0, 0], E: [2, 0, 0]}
links:
  beam1: {type: beam, from: O, to: A, material: steel, section: rod}
  beam2: {type: beam, from: A, to: E, material: {E: 7e10, nu: 0.33, density: 2700}, section: rod}
supports:
  base: {type: rigid, at: O, displacement: [0, 0, -0.001, 0, 0, 0]}
loads:
  - {at: E, wrench: [0, 0, -1000, 0, 0, 0]}
  - {link: beam1, distributed: [0, 0, -500]}
  - {link: beam1, distributed: {from: [0, 0, -100], to: [0, 0, -300]}}
  - {link: beam2, force: [0, 0, -200], moment: [0, 10, 0], position: 0.3}
  - {link: beam2, force: [0, 0, -50], position: 1}
load_cases:
  machining: [{at: E, wrench: [0, 0, -1000, 0, 0, 0]}, {link: beam2, distributed: [0, 1, 0]}]
  heavy: {loads: [{at: E, wrench: [1, 2, 3, 4, 5, 6]}], gravity: [0, -9.81, 0]}
  weight_only: {gravity: [0, 0, -9.81]}
end_effectors: {tip: {at: E}}
)";

TEST(ModelFile, ReadsLinkLoadsGravityDensitiesCasesSettlementsAndTheAnalysisMode) {
  const Model m = parse(kLoadedFrame);
  EXPECT_EQ(m.options.mode, AnalysisMode::loaded);
  EXPECT_EQ(m.options.load_steps, 12);
  ASSERT_TRUE(m.gravity.has_value());
  EXPECT_EQ(*m.gravity, Vec3(0, 0, -9.81));
  EXPECT_EQ(std::get<BeamLink>(link_named(m, "beam1").kind).material.density, 7850.0);
  EXPECT_EQ(std::get<BeamLink>(link_named(m, "beam2").kind).material.density, 2700.0);
  ASSERT_TRUE(m.supports[0].displacement.has_value());
  EXPECT_EQ(*m.supports[0].displacement, (Vec6() << 0, 0, -0.001, 0, 0, 0).finished());

  // The point load and the link loads of one list land in their own lists, in file order.
  ASSERT_EQ(m.loads.size(), 1u);
  EXPECT_EQ(m.loads[0].wrench(2), -1000.0);
  ASSERT_EQ(m.link_loads.size(), 4u);
  EXPECT_EQ(m.link_loads[0].link, "beam1");
  const auto& uniform = std::get<DistributedLinkLoad>(m.link_loads[0].load);
  EXPECT_EQ(uniform.from, Vec3(0, 0, -500));
  EXPECT_EQ(uniform.to, Vec3(0, 0, -500));
  const auto& varying = std::get<DistributedLinkLoad>(m.link_loads[1].load);
  EXPECT_EQ(varying.from, Vec3(0, 0, -100));
  EXPECT_EQ(varying.to, Vec3(0, 0, -300));
  const auto& point = std::get<PointLinkLoad>(m.link_loads[2].load);
  EXPECT_EQ(m.link_loads[2].link, "beam2");
  EXPECT_EQ(point.force, Vec3(0, 0, -200));
  EXPECT_EQ(point.moment, Vec3(0, 10, 0));
  EXPECT_EQ(point.position, 0.3);
  const auto& without_moment = std::get<PointLinkLoad>(m.link_loads[3].load);
  EXPECT_EQ(without_moment.moment, Vec3::Zero());
  EXPECT_EQ(without_moment.position, 1.0);
  EXPECT_EQ(m.link_loads[2].origin.location.line, 16);
  EXPECT_EQ(m.link_loads[2].origin.of("position").line, 16);

  ASSERT_EQ(m.load_cases.size(), 3u);
  const LoadCase& machining = m.load_cases[0];
  EXPECT_EQ(machining.name, "machining");
  ASSERT_EQ(machining.loads.size(), 1u);
  EXPECT_EQ(machining.loads[0].at, "E");
  ASSERT_EQ(machining.link_loads.size(), 1u);
  EXPECT_EQ(std::get<DistributedLinkLoad>(machining.link_loads[0].load).to, Vec3(0, 1, 0));
  EXPECT_FALSE(machining.gravity.has_value());
  EXPECT_EQ(machining.origin.location.line, 19);
  const LoadCase& heavy = m.load_cases[1];
  EXPECT_EQ(heavy.name, "heavy");
  ASSERT_EQ(heavy.loads.size(), 1u);
  EXPECT_EQ(heavy.loads[0].wrench, (Vec6() << 1, 2, 3, 4, 5, 6).finished());
  EXPECT_EQ(heavy.gravity, Vec3(0, -9.81, 0));
  EXPECT_TRUE(m.load_cases[2].loads.empty());
  EXPECT_EQ(m.load_cases[2].gravity, Vec3(0, 0, -9.81));
}

TEST(ModelFile, AnalysisModeDefaultsToLinearWithNoLoadSteps) {
  const Model m = parse(kSpecExample);
  EXPECT_EQ(m.options.mode, AnalysisMode::linear);
  EXPECT_FALSE(m.options.load_steps.has_value());
  EXPECT_FALSE(m.gravity.has_value());
  EXPECT_TRUE(m.link_loads.empty());
  EXPECT_TRUE(m.load_cases.empty());
  EXPECT_FALSE(m.supports[0].displacement.has_value());
  EXPECT_FALSE(std::get<BeamLink>(m.links[0].kind).material.density.has_value());
  const Model linear = parse(R"(format: stiffmsa/1
analysis: {mode: linear}
points: {O: [0, 0, 0], A: [1, 0, 0]}
links: {L: {type: rigid, from: O, to: A}}
)");
  EXPECT_EQ(linear.options.mode, AnalysisMode::linear);
}

// A written model reads back to the same model: the same structure, every number the same.
TEST(ModelFile, AWrittenModelWithIssueTwentyTwoKeysReadsBackEqual) {
  Model m = parse(kLoadedFrame);
  m.options.load_steps.reset();  // written only where given
  LoadCase empty;
  empty.name = "nothing";
  m.add_load_case(empty);
  m.load_cases[0].loads[0].link = "beam2";
  const std::string text = model_to_yaml(m);
  const Model back = parse(text, "written.yaml");
  const Structure structure(m);
  EXPECT_EQ(structure.values_of(back), structure.default_values());
  EXPECT_EQ(back.options.mode, AnalysisMode::loaded);
  EXPECT_FALSE(back.options.load_steps.has_value());
  ASSERT_EQ(back.load_cases.size(), 4u);
  EXPECT_EQ(back.load_cases[0].loads[0].link, "beam2");
  EXPECT_EQ(back.load_cases[3].name, "nothing");
  EXPECT_TRUE(back.load_cases[3].loads.empty());
  EXPECT_FALSE(back.load_cases[3].gravity.has_value());
  EXPECT_EQ(model_to_yaml(back), text);
  m.options.load_steps = 7;
  EXPECT_EQ(parse(model_to_yaml(m), "written.yaml").options.load_steps, 7);
}

TEST(ModelFile, LoadsAFileFromDisk) {
  const auto path = std::filesystem::temp_directory_path() / "stiffmsa_test_model_file.yaml";
  {
    std::ofstream out(path);
    out << kSpecExample;
  }
  const Model m = load_model(path);
  std::filesystem::remove(path);
  EXPECT_EQ(m.name, "planar-2R-example");
  EXPECT_EQ(m.source_file, path.string());
  EXPECT_EQ(m.joints[0].origin.location.file, path.string());
}

TEST(ModelFile, AFileThatCannotBeReadIsAnIoErrorNamingThePath) {
  const auto path = std::filesystem::temp_directory_path() / "stiffmsa_no_such_dir" / "m.yaml";
  try {
    load_model(path);
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_model(std::filesystem::temp_directory_path()), IoError);
}

}  // namespace
}  // namespace stiffmsa
