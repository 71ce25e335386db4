// The builder's verbs and the result's lookups as a binding wraps them: indices that a later
// add_* leaves valid, connections by their factories, named materials and sections, results by
// name with the nearest name in the error, the solver as an enum.
#include <gtest/gtest.h>

#include "builders.hpp"
#include "stiffmsa/stiffmsa.hpp"

using namespace stiffmsa;

namespace {

const Material kAluminium{7.0e10, 0.33, std::nullopt};

// The planar 2R arm of examples/planar-2r.yaml, its beams' material and sections named.
Model named_arm() {
  Model m;
  m.add_material("aluminium", kAluminium);
  m.add_section("upper_box", Section::rect_tube(0.06, 0.08, 0.004));
  m.add_section("fore_box", Section::rect_tube(0.05, 0.06, 0.003));
  m.add_point("floor", {0, 0, -0.25});
  m.add_point("shoulder", {0, 0, 0});
  m.add_point("elbow", {0.48, 0.36, 0});
  m.add_point("tip", {0.21, 0.72, 0});
  m.add_rigid_link("pedestal", "floor", "shoulder");
  m.add_beam("upper_arm", "shoulder", "elbow", "aluminium", "upper_box");
  m.add_beam("forearm", "elbow", "tip", "aluminium", "fore_box");
  const Kinematics turning = Kinematics::revolute({0, 0, 1});
  m.add_joint("shoulder_joint", "shoulder", {"pedestal", "upper_arm"},
              Connection::elastic(turning, 2.0e5));
  m.add_joint("elbow_joint", "elbow", {"upper_arm", "forearm"},
              Connection::elastic(turning, 1.0e5));
  m.add_support("base", "floor", {}, Connection::rigid());
  m.add_load("tip", std::nullopt, stiffmsa::testing::wrench(50, -200, 0));
  m.add_end_effector("tool", "tip");
  return m;
}

}  // namespace

TEST(ModelVerbs, IndicesStayValidAfterLaterVerbs) {
  Model m;
  const PointIndex first = m.add_point("P0", Vec3::Zero());
  for (int i = 1; i <= 100; ++i) m.add_point("P" + std::to_string(i), Vec3(i, 0, 0));
  EXPECT_EQ(first.value, 0u);
  EXPECT_EQ(m.point(first).name, "P0");
  const LinkIndex rod = m.add_rigid_link("rod", "P0", "P1");
  for (int i = 2; i <= 100; ++i)
    m.add_rigid_link("L" + std::to_string(i), "P" + std::to_string(i - 1), "P" + std::to_string(i));
  m.link(rod).origin.location.line = 7;
  EXPECT_EQ(m.links[0].origin.location.line, 7);
  EXPECT_EQ(m.support(m.add_support("S", "P0", {}, Connection::rigid())).name, "S");
  EXPECT_THROW(m.joint(JointIndex{0}), std::out_of_range);
}

TEST(ModelVerbs, NamedMaterialsAndSectionsGiveTheBeamsTheirValues) {
  const Model named = named_arm();
  const BeamLink& upper = std::get<BeamLink>(named.links[1].kind);
  EXPECT_EQ(upper.material.E, kAluminium.E);
  EXPECT_EQ(upper.section.t, 0.004);
  // The same arm with the values given directly solves to the same numbers, bit for bit.
  Model direct = named;
  direct.materials.clear();
  direct.sections.clear();
  direct.links[1].kind =
      BeamLink{kAluminium, Section::rect_tube(0.06, 0.08, 0.004), false, std::nullopt};
  EXPECT_EQ(*solve(named).end_effector("tool").compliance,
            *solve(direct).end_effector("tool").compliance);
}

TEST(ModelVerbs, AnUnknownMaterialOrSectionNamesTheNearest) {
  Model m = named_arm();
  try {
    m.add_beam("extra", "elbow", "tip", "aluminum", "fore_box");
    FAIL() << "no error";
  } catch (const NameError& e) {
    EXPECT_EQ(e.kind(), "material");
    EXPECT_EQ(e.name(), "aluminum");
    EXPECT_EQ(e.suggestion(), "aluminium");
    EXPECT_STREQ(e.what(), "there is no material 'aluminum'; did you mean 'aluminium'?");
  }
  EXPECT_THROW(m.add_beam("extra", "elbow", "tip", "aluminium", "box"), NameError);
  EXPECT_THROW(m.add_material("aluminium", kAluminium), UsageError);
  EXPECT_THROW(m.add_section("fore_box", Section::circle(0.1)), UsageError);
}

TEST(Connections, FactoriesSayWhatTheConnectionIs) {
  const Kinematics hinge = Kinematics::revolute(Vec3::UnitZ());
  EXPECT_EQ(Connection::rigid().kinematics.type, JointType::rigid);
  const Connection passive = Connection::passive(hinge);
  EXPECT_FALSE(passive.stiffness || passive.preload || passive.is_actuated);
  const Connection spring = Connection::elastic(hinge, 1e4);
  EXPECT_EQ(*spring.stiffness, MatX::Constant(1, 1, 1e4));
  EXPECT_FALSE(spring.is_actuated);
  const Connection motor = Connection::actuated(hinge);
  EXPECT_TRUE(motor.is_actuated);
  EXPECT_FALSE(motor.stiffness);
  const Connection drive = Connection::actuated(hinge, 3e4).preloaded(2.5);
  EXPECT_TRUE(drive.is_actuated);
  EXPECT_EQ(*drive.stiffness, MatX::Constant(1, 1, 3e4));
  EXPECT_EQ(*drive.preload, VecX::Constant(1, 2.5));
  const Connection ball =
      Connection::elastic(Kinematics::spherical(), MatX(2e3 * Mat3::Identity()));
  EXPECT_EQ(ball.stiffness->rows(), 3);
}

TEST(Connections, AScalarIsForOneFreeDirection) {
  try {
    Connection::elastic(Kinematics::spherical(), 1e4);
    FAIL() << "no error";
  } catch (const UsageError& e) {
    EXPECT_STREQ(
        e.what(),
        "a scalar stiffness is for a connection with one free direction; a spherical one has 3: "
        "give a p×p matrix");
  }
  EXPECT_THROW(
      Connection::passive(Kinematics::universal(Vec3::UnitX(), Vec3::UnitY())).preloaded(1.0),
      UsageError);
}

TEST(Results, LookedUpByNameAsInModelOrder) {
  const Result r = solve(named_arm());
  EXPECT_EQ(&r.end_effector("tool"), &r.end_effectors[0]);
  EXPECT_EQ(&r.link("forearm"), &r.links[2]);
  EXPECT_EQ(&r.joint("elbow_joint"), &r.joints[1]);
  EXPECT_EQ(&r.support("base"), &r.supports[0]);
  try {
    (void)r.joint("elbow_jiont");
    FAIL() << "no error";
  } catch (const NameError& e) {
    EXPECT_STREQ(e.what(), "there is no joint 'elbow_jiont'; did you mean 'elbow_joint'?");
  }
  try {
    (void)r.end_effector("gripper");
    FAIL() << "no error";
  } catch (const NameError& e) {
    EXPECT_FALSE(e.suggestion());
    EXPECT_STREQ(e.what(), "there is no end effector 'gripper'; there are end effectors: tool");
  }
}

TEST(Results, TheSolverIsAnEnumWithItsName) {
  const Result r = solve(named_arm());
  EXPECT_EQ(r.report.solver, SolverUsed::tree);
  EXPECT_STREQ(to_string(r.report.solver), "tree");
  EXPECT_EQ(solver_used_from_string("tree_with_cuts"), SolverUsed::tree_with_cuts);
  EXPECT_FALSE(solver_used_from_string("cholesky"));
  EXPECT_TRUE(r.report.usable());
  SolveReport failed = r.report;
  failed.failed_checks.push_back("the relative residual 1e-3 exceeds 1e-10");
  EXPECT_FALSE(failed.usable());
}

TEST(Results, NamesAreListedTheOneWay) {
  EXPECT_EQ(name_list({}), "");
  EXPECT_EQ(name_list({"a"}), "a");
  EXPECT_EQ(name_list({"a", "b", "c"}), "a, b, c");
  EXPECT_EQ(name_list({"a", "b", "c"}, " and "), "a, b and c");
  EXPECT_EQ(name_list({"a", "b", "c", "d"}, " and ", 2), "a, b and 2 more");
}
