// Mechanisms named by their culprit (the passive joints and supports that let a free motion
// happen, parts that nothing holds), and the stiffness of end effectors held rigidly in some
// directions on the directions they can move in (reduced_stiffness).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <string>

#include "closed_forms.hpp"
#include "stiffmsa/analysis.hpp"
#include "stiffmsa/io/model_file.hpp"
#include "stiffmsa/io/result_file.hpp"

namespace {

using reference::relative_difference;
using stiffmsa::Mat6;
using stiffmsa::MatX;
using stiffmsa::Model;
using stiffmsa::Result;
using stiffmsa::SingularModelError;
using stiffmsa::Vec3;
using stiffmsa::Vec6;

std::size_t occurrences(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

// The error a model's solve throws (the test fails where it solves).
SingularModelError refusal(const Model& model) {
  try {
    stiffmsa::solve(model);
  } catch (const SingularModelError& error) {
    return error;
  }
  ADD_FAILURE() << "the mechanism was solved";
  return SingularModelError(SingularModelError::Cause::numerical, "", {});
}

// A planar five-bar: two cranks from the ground (motors at A1 and A2), two rods meeting at P.
// The second motor is left passive: a free motion, the second crank turning with the loop.
std::string five_bar(const std::string& motor2) {
  return R"(format: stiffmsa/1
name: five-bar
materials:
  aluminium: {E: 7.0e10, nu: 0.33}
sections:
  bar: {shape: circle, D: 0.02}
points:
  A1: [0, 0, 0]
  A2: [0.2, 0, 0]
  B1: [-0.03, 0.15, 0]
  B2: [0.23, 0.15, 0]
  P:  [0.1, 0.32, 0]
links:
  crank_1: {type: beam, from: A1, to: B1, material: aluminium, section: bar}
  crank_2: {type: beam, from: A2, to: B2, material: aluminium, section: bar}
  rod_1:   {type: beam, from: B1, to: P, material: aluminium, section: bar}
  rod_2:   {type: beam, from: B2, to: P, material: aluminium, section: bar}
joints:
  elbow_1: {type: revolute, at: B1, links: [crank_1, rod_1], axis: [0, 0, 1]}
  elbow_2: {type: revolute, at: B2, links: [crank_2, rod_2], axis: [0, 0, 1]}
  tip:     {type: revolute, at: P, links: [rod_1, rod_2], axis: [0, 0, 1]}
supports:
  motor1: {type: revolute, at: A1, axis: [0, 0, 1], actuated: true, stiffness: 2.0e4}
  motor2: {type: revolute, at: A2, axis: [0, 0, 1])" +
         motor2 + R"(}
loads:
  - {at: P, link: rod_1, wrench: [10, -20, 0, 0, 0, 0]}
end_effectors:
  tool: {at: P, link: rod_1}
)";
}

TEST(MechanismCulprits, FiveBarWithAPassiveMotorNamesTheMotor) {
  const SingularModelError error = refusal(stiffmsa::parse_model(five_bar(""), "five-bar.yaml"));
  EXPECT_EQ(error.cause(), SingularModelError::Cause::free_motion);
  const std::string text = error.what();
  // The first line is a sentence; what() carries the details after it.
  EXPECT_EQ(text.substr(0, text.find('\n')),
            "the model is a mechanism with 1 free motion and carries loads or preloads, which a "
            "mechanism cannot "
            "hold (only an unloaded one is solved)")
      << text;
  EXPECT_EQ(error.summary(), text.substr(0, text.find('\n')));
  ASSERT_EQ(error.details().size(), 2u) << text;
  EXPECT_EQ(error.details()[0],
            "free motion 1: passive support 'motor2' (revolute at A2) and passive joints 'elbow_1' "
            "(revolute at B1), "
            "'elbow_2' (revolute at B2), 'tip' (revolute at P) let it happen; it moves links "
            "'crank_2', 'rod_1', "
            "'rod_2' and end effector 'tool'")
      << text;
  EXPECT_EQ(error.details()[1],
            "to stop a free motion, give a joint or support that lets it happen a `stiffness:` "
            "(elastic) or "
            "`actuated: true` (a motor, locked where it stands)");
  EXPECT_NE(text.find("\n  free motion 1: passive support 'motor2'"), std::string::npos) << text;
  // motor1 is elastic: it resists, and is no culprit; its crank stays.
  EXPECT_EQ(text.find("motor1"), std::string::npos) << text;
  EXPECT_EQ(text.find("crank_1"), std::string::npos) << text;

  // The fix the message suggests solves the model.
  const Result fixed = stiffmsa::solve(
      stiffmsa::parse_model(five_bar(", actuated: true, stiffness: 2.0e4"), "five-bar.yaml"));
  EXPECT_TRUE(fixed.end_effectors[0].deflection);
}

// A UR5-like arm: six revolute axes, the first of them a support (the base joint).
std::string ur5_like(const std::string& base, const std::string& wrist_3) {
  return R"(format: stiffmsa/1
name: ur5-like
materials:
  steel: {E: 2.1e11, nu: 0.3}
sections:
  tube: {shape: tube, D: 0.08, t: 0.005}
points:
  floor:    [0, 0, 0]
  shoulder: [0, 0, 0.089]
  elbow:    [0.425, 0, 0.089]
  wrist_1:  [0.817, 0, 0.089]
  wrist_2:  [0.817, 0.109, 0.089]
  wrist_3:  [0.817, 0.109, -0.006]
  tcp:      [0.817, 0.191, -0.006]
links:
  base_link:   {type: rigid, from: floor, to: shoulder}
  upper_arm:   {type: beam, from: shoulder, to: elbow, material: steel, section: tube}
  forearm:     {type: beam, from: elbow, to: wrist_1, material: steel, section: tube}
  wrist_link_1: {type: rigid, from: wrist_1, to: wrist_2}
  wrist_link_2: {type: rigid, from: wrist_2, to: wrist_3}
  flange:      {type: rigid, from: wrist_3, to: tcp}
joints:
  shoulder_joint: {type: revolute, at: shoulder, links: [base_link, upper_arm], axis: [0, 1, 0], actuated: true, stiffness: 3.0e5}
  elbow_joint:    {type: revolute, at: elbow, links: [upper_arm, forearm], axis: [0, 1, 0], actuated: true, stiffness: 2.0e5}
  wrist_1_joint:  {type: revolute, at: wrist_1, links: [forearm, wrist_link_1], axis: [0, 1, 0], actuated: true, stiffness: 5.0e4}
  wrist_2_joint:  {type: revolute, at: wrist_2, links: [wrist_link_1, wrist_link_2], axis: [0, 0, 1], actuated: true, stiffness: 5.0e4}
  wrist_3_joint:  {type: revolute, at: wrist_3, links: [wrist_link_2, flange], axis: [0, 1, 0])" +
         wrist_3 + R"(}
supports:
  base_joint: {type: revolute, at: floor, axis: [0, 0, 1])" +
         base + R"(}
loads:
  - {at: tcp, wrench: [20, 0, -50, 0, 0, 0]}
end_effectors:
  tool: {at: tcp}
)";
}

constexpr const char* kElastic = ", actuated: true, stiffness: 5.0e4";

TEST(MechanismCulprits, ArmWithAPassiveBaseJointNamesTheSupport) {
  const SingularModelError error =
      refusal(stiffmsa::parse_model(ur5_like("", kElastic), "ur5.yaml"));
  ASSERT_EQ(error.details().size(), 2u) << error.what();
  EXPECT_EQ(error.details()[0],
            "free motion 1: passive support 'base_joint' (revolute at floor) lets it happen; it "
            "moves links "
            "'base_link', 'upper_arm', 'forearm', 'wrist_link_1', 'wrist_link_2', 'flange' and end "
            "effector 'tool'")
      << error.what();
  EXPECT_TRUE(std::string(error.what())
                  .starts_with("the model is a mechanism with 1 free motion and carries loads"));
}

TEST(MechanismCulprits, IndependentFreeMotionsAreToldApart) {
  // The base and the last wrist joint both passive: two motions, each named by its own culprit
  // alone rather than as two mixtures of both.
  const SingularModelError error = refusal(stiffmsa::parse_model(ur5_like("", ""), "ur5.yaml"));
  const std::string text = error.what();
  EXPECT_TRUE(text.starts_with("the model is a mechanism with 2 free motions")) << text;
  ASSERT_EQ(error.details().size(), 3u) << text;
  EXPECT_TRUE(error.details()[0].starts_with(
      "free motion 1: passive support 'base_joint' (revolute at floor) lets it happen;"))
      << text;
  EXPECT_EQ(error.details()[0].find("wrist_3_joint"), std::string::npos) << text;
  EXPECT_EQ(error.details()[1],
            "free motion 2: passive joint 'wrist_3_joint' (revolute at wrist_3) lets it happen; it "
            "moves link "
            "'flange' and end effector 'tool'")
      << text;
}

TEST(MechanismCulprits, MotionsOfOneJointShareOneLine) {
  // A ball joint lets three motions happen: one line for the three, not three alike.
  Model model = stiffmsa::parse_model(ur5_like(kElastic, kElastic), "ur5.yaml");
  auto& wrist = model.joints.back().connection;
  wrist.kinematics = stiffmsa::Kinematics::spherical();
  wrist.is_actuated = false;
  wrist.stiffness.reset();
  const SingularModelError error = refusal(model);
  ASSERT_EQ(error.details().size(), 2u) << error.what();
  EXPECT_EQ(error.details()[0],
            "free motions 1, 2 and 3: passive joint 'wrist_3_joint' (spherical at wrist_3) lets "
            "them happen; they "
            "move link 'flange' and end effector 'tool'")
      << error.what();
}

TEST(MechanismCulprits, MotionThatNoEndEffectorStopsIsRefusedUnloaded) {
  // The end effector on the wrist's first link: the passive last joint turns the flange, which
  // no end effector holds, so not even an unloaded solve has anything to report.
  Model model = stiffmsa::parse_model(ur5_like(kElastic, ""), "ur5.yaml");
  model.loads.clear();
  model.end_effectors[0].at = "wrist_2";
  model.end_effectors[0].link = "wrist_link_1";
  const SingularModelError error = refusal(model);
  EXPECT_EQ(error.summary(),
            "the model is a mechanism with 1 free motion, and no end effector stops it");
  ASSERT_EQ(error.details().size(), 2u) << error.what();
  EXPECT_EQ(error.details()[0],
            "free motion 1: passive joint 'wrist_3_joint' (revolute at wrist_3) lets it happen; it "
            "moves link "
            "'flange'; it moves no end effector (an idle motion: accept it with `options: "
            "{accept_idle_motions: "
            "true}` in the model or SolveOptions::accept_idle_motions)")
      << error.what();

  auto& wrist = model.joints.back().connection;
  wrist.kinematics = stiffmsa::Kinematics::spherical();
  const SingularModelError three = refusal(model);
  EXPECT_EQ(three.summary(),
            "the model is a mechanism with 3 free motions, and no end effector stops them");
  ASSERT_EQ(three.details().size(), 2u) << three.what();
  EXPECT_EQ(
      three.details()[0],
      "free motions 1, 2 and 3: passive joint 'wrist_3_joint' (spherical at wrist_3) lets them "
      "happen; they "
      "move link 'flange'; they move no end effector (idle motions: accept them with `options: "
      "{accept_idle_motions: true}` in the model or SolveOptions::accept_idle_motions)")
      << three.what();
}

// A planar arm whose forearm starts at a point of its own, at the elbow's coordinates: meant to
// be welded to the upper arm, it is joined to nothing.
constexpr const char* kDetachedForearm = R"(format: stiffmsa/1
name: detached
materials:
  steel: {E: 2.1e11, nu: 0.3}
sections:
  bar: {shape: circle, D: 0.03}
points:
  shoulder: [0, 0, 0]
  elbow:    [0.5, 0, 0]
  elbow_b:  [0.5, 0, 0]
  tip:      [0.9, 0.2, 0]
links:
  upper_arm: {type: beam, from: shoulder, to: elbow, material: steel, section: bar}
  forearm:   {type: beam, from: elbow_b, to: tip, material: steel, section: bar}
supports:
  clamp: {type: rigid, at: shoulder}
loads:
  - {at: tip, wrench: [0, -10, 0, 0, 0, 0]}
end_effectors:
  tool: {at: tip}
)";

TEST(MechanismCulprits, LinkConnectedToNothingIsSaidOnce) {
  const SingularModelError error =
      refusal(stiffmsa::parse_model(kDetachedForearm, "detached.yaml"));
  const std::string text = error.what();
  EXPECT_TRUE(text.starts_with("the model is a mechanism with 6 free motions and carries loads"))
      << text;
  ASSERT_EQ(error.details().size(), 1u) << text;
  EXPECT_EQ(error.details()[0],
            "link 'forearm' is connected to nothing at its start: its point 'elbow_b' stands where "
            "point 'elbow' "
            "is, but points are told apart by name, not by coordinates");
  EXPECT_EQ(occurrences(text, "forearm"), 1u) << text;
}

// The cantilever of tests/test_cli.cpp without its support.
std::string unsupported_rod(const std::string& loads) {
  return R"(format: stiffmsa/1
name: floating
points:
  O: [0, 0, 0]
  E: [1, 0, 0]
links:
  L1: {type: beam, from: O, to: E, material: {E: 2.1e11, nu: 0.3}, section: {shape: circle, D: 0.05}}
)" + loads +
         R"(end_effectors:
  EE: {at: E, link: L1}
)";
}

TEST(MechanismCulprits, ModelWithoutSupportIsSaidOnce) {
  const SingularModelError error = refusal(stiffmsa::parse_model(
      unsupported_rod("loads:\n  - {at: E, wrench: [0, -100, 0, 0, 0, 0]}\n"), "f.yaml"));
  const std::string text = error.what();
  EXPECT_TRUE(text.starts_with("the model is a mechanism with 6 free motions")) << text;
  ASSERT_EQ(error.details().size(), 1u) << text;
  EXPECT_EQ(error.details()[0],
            "the model has no support: nothing holds it, so it can move as a whole; add one under "
            "`supports:`");
}

TEST(MechanismCulprits, UnloadedModelWithoutSupportWarnsThatItsStiffnessIsZero) {
  const Result result = stiffmsa::solve(stiffmsa::parse_model(unsupported_rod(""), "f.yaml"));
  ASSERT_TRUE(result.end_effectors[0].stiffness);
  EXPECT_EQ(*result.end_effectors[0].stiffness, Mat6::Zero());
  ASSERT_EQ(result.report.warnings.size(), 1u);
  EXPECT_EQ(result.report.warnings[0],
            "the model has no support: nothing holds it, so the stiffness of its end effectors is "
            "zero (it measures "
            "only what holds the end effector against the rest of the model); add a support under "
            "`supports:`");
  // A supported model gets no such warning.
  Model held = stiffmsa::parse_model(unsupported_rod(""), "f.yaml");
  held.add_support("clamp", "O", {}, {});
  EXPECT_TRUE(stiffmsa::solve(held).report.warnings.empty());
}

TEST(MechanismCulprits, PartThatNoSupportReachesIsNamedOnce) {
  // A stray link between points of its own, beside a supported rod.
  Model model = stiffmsa::parse_model(
      unsupported_rod("loads:\n  - {at: E, wrench: [0, -100, 0, 0, 0, 0]}\n"), "f.yaml");
  model.add_support("clamp", "O", {}, {});
  model.add_point("S1", Vec3(0, 1, 0));
  model.add_point("S2", Vec3(0, 2, 0));
  model.add_rigid_link("stray", "S1", "S2");
  const SingularModelError error = refusal(model);
  EXPECT_EQ(error.summary(),
            "the model is a mechanism with 6 free motions and carries loads or preloads, which a "
            "mechanism cannot "
            "hold (only an unloaded one is solved)");
  ASSERT_EQ(error.details().size(), 1u) << error.what();
  EXPECT_EQ(error.details()[0],
            "link 'stray' is held by no support: no joint, support or shared point joins it to a "
            "supported part, so "
            "it can move as a whole");
  model.add_point("S3", Vec3(0, 3, 0));
  model.add_rigid_link("stray_2", "S2", "S3");
  EXPECT_EQ(refusal(model).details()[0],
            "links 'stray', 'stray_2' are held by no support: no joint, support or shared point "
            "joins them to a "
            "supported part, so they can move as a whole");
}

}  // namespace
