// Every closed form of theory-notes.md, pinned at tight relative tolerances.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "builders.hpp"
#include "closed_forms.hpp"
#include "stiffmsa/stiffmsa.hpp"

using namespace stiffmsa;
using reference::relative_difference;
using reference::relative_difference_scaled;

namespace {

constexpr double kE = 2.1e11;
constexpr double kG = 8.0e10;
const Material kSteel{kE, std::nullopt, kG};

using stiffmsa::testing::wrench;

void expect_healthy(const Result& r) {
  EXPECT_LT(r.report.relative_residual, 1e-12);
  EXPECT_LT(r.report.equilibrium_error, 1e-11);
  EXPECT_TRUE(r.report.warnings.empty());
}

// A straight cantilever along local x from O, split into `segments` beam links.
Model cantilever(int segments, double length, const Section& section, bool shear = false) {
  Model m = stiffmsa::testing::beam_chain(
      segments, [&](int i) { return Vec3(length * i / segments, 0, 0); }, kSteel, section);
  for (Link& link : m.links) std::get<BeamLink>(link.kind).shear = shear;
  return m;
}

}  // namespace

TEST(Cantilever, EulerBernoulliTipComplianceMatchesTextbook) {
  const double L = 0.8, b = 0.04, h = 0.07;
  Model m = cantilever(1, L, Section::rect(b, h));
  m.add_load("P1", std::nullopt, wrench(0, 0, -250));
  const Result r = solve(m);
  expect_healthy(r);
  const double A = b * h, Iy = b * h * h * h / 12, Iz = h * b * b * b / 12;
  const double a = h, c = b;  // Roark's solid-rectangle torsion constant
  const double J = a * c * c * c * (1.0 / 3 - 0.21 * (c / a) * (1 - std::pow(c / a, 4) / 12));
  const Mat6 expected = reference::cantilever_compliance(L, kE, kG, A, Iy, Iz, J);
  EXPECT_LT(relative_difference_scaled(*r.end_effectors[0].compliance, expected), 1e-12);
  // Tip deflection under the load: w = F·L³/(3EIy), rotation about y = −F·L²/(2EIy) (w' = −θy).
  const Vec6 d = *r.end_effectors[0].deflection;
  EXPECT_NEAR(d(2) / (-250 * L * L * L / (3 * kE * Iy)), 1.0, 1e-12);
  EXPECT_NEAR(d(4) / (250 * L * L / (2 * kE * Iy)), 1.0, 1e-12);
  // The support carries the load back: reaction = −load moved to the root.
  EXPECT_LT(relative_difference(*r.supports[0].reaction, wrench(0, 0, 250, 0, -250 * L, 0)), 1e-12);
  ASSERT_TRUE(r.end_effectors[0].stiffness);
  EXPECT_LT(
      relative_difference(Mat6(*r.end_effectors[0].stiffness * *r.end_effectors[0].compliance),
                          Mat6(Mat6::Identity())),
      1e-10);
}

TEST(Cantilever, TimoshenkoAddsShearFlexibility) {
  const double L = 0.3, D = 0.06, t = 0.004;
  const Model m = cantilever(1, L, Section::tube(D, t), true);
  const Result r = solve(m);
  const double d = D - 2 * t, pi = std::numbers::pi;
  const double A = pi * (D * D - d * d) / 4, I = pi * (std::pow(D, 4) - std::pow(d, 4)) / 64;
  const Mat6 expected =
      reference::cantilever_compliance(L, kE, kG, A, I, I, 2 * I, 0.5 * A, 0.5 * A);
  EXPECT_LT(relative_difference_scaled(*r.end_effectors[0].compliance, expected), 1e-12);
}

TEST(Cantilever, ChainOf200BeamLinksKeepsNineDigits) {
  const double L = 2.0;
  const Model m = cantilever(200, L, Section::circle(0.05));
  const Result r = solve(m);
  EXPECT_EQ(r.system.unknowns, 200 * 24);
  EXPECT_EQ(r.system.equations, 200 * 24);
  const double pi = std::numbers::pi, A = pi * 0.05 * 0.05 / 4, I = pi * std::pow(0.05, 4) / 64;
  const Mat6 expected = reference::cantilever_compliance(L, kE, kG, A, I, I, 2 * I);
  EXPECT_LT(relative_difference_scaled(*r.end_effectors[0].compliance, expected), 1e-9);
  EXPECT_LT(r.report.relative_residual, 1e-12);
}

// The issue asks for 1e-7 at 10 000 links. A pivoting LU alone keeps about 1.6e-13 here with
// KLU (the system's condition is ~2e5); refinement with an extended-precision residual
// recovers the rest, with every backend.
TEST(Cantilever, ChainOf10000BeamLinksKeepsFourteenDigitsWithEverySolver) {
  const double L = 10.0;
  const Model m = cantilever(10000, L, Section::tube(0.1, 0.005));
  const double pi = std::numbers::pi, d = 0.09;
  const double A = pi * (0.01 - d * d) / 4, I = pi * (1e-4 - std::pow(d, 4)) / 64;
  const Mat6 expected = reference::cantilever_compliance(L, kE, kG, A, I, I, 2 * I);
  for (SolverKind kind :
       {SolverKind::automatic, SolverKind::sparse_lu, SolverKind::umfpack, SolverKind::klu}) {
    if (!solver_available(kind)) continue;
    SolveOptions options;
    options.solver = kind;
    const Result r = solve(m, options);
    EXPECT_LT(relative_difference_scaled(*r.end_effectors[0].compliance, expected), 1e-14)
        << to_string(kind);
  }
}

// VJM: a serial chain of rigid links with elastic revolute joints, C = Σ J_i·k_i⁻¹·J_iᵀ.
TEST(SerialChain, RigidLinksElasticJointsMatchVirtualJointModel) {
  const std::vector<Vec3> points = {
      {0, 0, 0}, {0, 0, 0.4}, {0.3, 0.1, 0.7}, {0.8, -0.2, 0.9}, {1.1, 0.0, 0.6}};
  const std::vector<Vec3> axes = {{0, 0, 1}, {0, 1, 0.2}, {0.3, 1, 0}, {1, 0, 0.1}};
  const std::vector<double> k = {2e6, 1.5e6, 8e5, 3e5};
  Model m;
  for (std::size_t i = 0; i < points.size(); ++i) m.add_point("P" + std::to_string(i), points[i]);
  m.add_point("B", Vec3(0, 0, -0.2));
  m.add_rigid_link("base", "B", "P0");
  m.add_support("ground", "B", {}, Connection::rigid());
  // Each joint sits at P_i between the previous link and link i, which runs to P_{i+1}.
  std::string previous = "base";
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    const std::string link = "L" + std::to_string(i + 1);
    m.add_rigid_link(link, "P" + std::to_string(i), "P" + std::to_string(i + 1));
    m.add_joint("J" + std::to_string(i + 1), "P" + std::to_string(i), {previous, link},
                Connection::elastic(Kinematics::revolute(axes[i]), k[i]));
    previous = link;
  }
  m.add_end_effector("tool", "P4");
  const Result r = solve(m);
  expect_healthy(r);

  Mat6 expected = Mat6::Zero();
  for (std::size_t i = 0; i < axes.size(); ++i) {
    const Vec3 a = axes[i].normalized();
    Vec6 column;
    column << a.cross(points.back() - points[i]), a;
    expected += column * column.transpose() / k[i];
  }
  const Mat6 C = *r.end_effectors[0].compliance;
  EXPECT_LT(relative_difference(C, expected), 1e-11);
  // Four joints give rank 4: the other two directions are held rigidly.
  EXPECT_FALSE(r.end_effectors[0].stiffness.has_value());
}

// With flexible links, each link adds its cantilever compliance carried to the end effector.
TEST(SerialChain, FlexibleLinksAddTheirTransportedCantileverCompliance) {
  const Vec3 p0(0, 0, 0), p1(0.5, 0.2, 0.3), p2(0.9, 0.6, 0.1);
  const double D = 0.05, k1 = 4e5, k2 = 2e5;
  const Vec3 a1 = Vec3(0, 0, 1), a2 = Vec3(0.2, 0.3, 1).normalized();
  Model m;
  m.add_point("P0", p0);
  m.add_point("P1", p1);
  m.add_point("P2", p2);
  m.add_point("B", Vec3(0, 0, -0.1));
  m.add_rigid_link("base", "B", "P0");
  m.add_support("ground", "B", {}, Connection::rigid());
  m.add_beam("L1", "P0", "P1", kSteel, Section::circle(D));
  m.add_beam("L2", "P1", "P2", kSteel, Section::circle(D));
  m.add_joint("J1", "P0", {"base", "L1"}, Connection::elastic(Kinematics::revolute(a1), k1));
  m.add_joint("J2", "P1", {"L1", "L2"}, Connection::elastic(Kinematics::revolute(a2), k2));
  m.add_end_effector("tip", "P2");
  const Result r = solve(m);
  expect_healthy(r);

  const double pi = std::numbers::pi, A = pi * D * D / 4, I = pi * std::pow(D, 4) / 64;
  auto link_compliance_at_tip = [&](const Vec3& from, const Vec3& to) {
    const double L = (to - from).norm();
    // A circular section makes the local y, z choice irrelevant: any orthonormal frame will do.
    const Vec3 x = (to - from) / L;
    const Vec3 y = x.unitOrthogonal(), z = x.cross(y);
    Mat3 R;
    R.col(0) = x;
    R.col(1) = y;
    R.col(2) = z;
    const Mat6 local = reference::cantilever_compliance(L, kE, kG, A, I, I, 2 * I);
    const Mat6 global = reference::rotate6(R) * local * reference::rotate6(R).transpose();
    const Mat6 carry = reference::twist_transport(p2 - to);
    return Mat6(carry * global * carry.transpose());
  };
  Mat6 expected = link_compliance_at_tip(p0, p1) + link_compliance_at_tip(p1, p2);
  for (const auto& [a, p, k] : {std::tuple{a1, p0, k1}, std::tuple{a2, p1, k2}}) {
    Vec6 column;
    column << a.cross(p2 - p), a;
    expected += column * column.transpose() / k;
  }
  EXPECT_LT(relative_difference_scaled(*r.end_effectors[0].compliance, expected), 1e-10);
}

// Two bars hinged at both ends meeting at a loaded apex, at ±α from vertical.
TEST(Truss, TwoHingedBarsGiveAxialStiffnessOnly) {
  const double L = 1.2, alpha = 0.5, D = 0.03;
  Model m;
  m.add_point("left", Vec3(-L * std::sin(alpha), 0, 0));
  m.add_point("right", Vec3(L * std::sin(alpha), 0, 0));
  m.add_point("apex", Vec3(0, 0, L * std::cos(alpha)));
  m.add_beam("bar1", "left", "apex", kSteel, Section::circle(D));
  m.add_beam("bar2", "right", "apex", kSteel, Section::circle(D));
  const auto hinge = Kinematics::revolute(Vec3::UnitY());
  m.add_support("S1", "left", {}, Connection::passive(hinge));
  m.add_support("S2", "right", {}, Connection::passive(hinge));
  m.add_joint("apex_hinge", "apex", {"bar1", "bar2"}, Connection::passive(hinge));
  m.add_end_effector("apex", "apex", "bar1");
  const Result r = solve(m);
  expect_healthy(r);
  const double EA_L = kE * std::numbers::pi * D * D / 4 / L;
  const Mat6& C = *r.end_effectors[0].compliance;
  EXPECT_NEAR(C(0, 0) * 2 * EA_L * std::pow(std::sin(alpha), 2), 1.0, 1e-10);
  EXPECT_NEAR(C(2, 2) * 2 * EA_L * std::pow(std::cos(alpha), 2), 1.0, 1e-10);
  EXPECT_LT(std::abs(C(0, 2)), 1e-10 * C(0, 0));
}

// A platform on legs: K_platform = Σ D_iᵀ·K_leg,i·D_i, legs clamped cantilevers.
// A beam clamped at both ends, loaded at midspan: the second support closes a loop through the
// ground, which the tree solve cuts at its reaction (docs/theory.md §7.2). By symmetry each
// half is a beam clamped at its far end whose midspan end neither turns under a force nor moves
// under a moment: C = diag(L/(4EA), L³/(192EI), L³/(192EI), L/(4GJ), L/(16EI), L/(16EI)).
// The chain tolerances (1e-9 at 200 links, 1e-7 at 10 000) hold with digits to spare.
TEST(ClampedClampedBeam, MidspanComplianceMatchesTheClosedFormThroughTheCutReaction) {
  const double L = 4.0, D = 0.08;
  const double pi = std::numbers::pi, A = pi * D * D / 4, I = pi * std::pow(D, 4) / 64, J = 2 * I;
  Vec6 diagonal;
  diagonal << L / (4 * kE * A), std::pow(L, 3) / (192 * kE * I), std::pow(L, 3) / (192 * kE * I),
      L / (4 * kG * J), L / (16 * kE * I), L / (16 * kE * I);
  const Mat6 expected = diagonal.asDiagonal();
  for (const int segments : {200, 10000}) {
    Model m = cantilever(segments, L, Section::circle(D));
    m.add_support("far", "P" + std::to_string(segments), {}, Connection::rigid());
    m.end_effectors.clear();
    m.add_end_effector("mid", "P" + std::to_string(segments / 2),
                       "L" + std::to_string(segments / 2));
    const Result r = solve(m);
    EXPECT_EQ(r.report.solver, stiffmsa::SolverUsed::tree_with_cuts) << segments;
    expect_healthy(r);
    EXPECT_LT(relative_difference_scaled(*r.end_effectors[0].compliance, expected), 1e-12)
        << segments;
  }
}

TEST(Parallel, PlatformStiffnessIsTheSumOfTransportedLegStiffnesses) {
  const Vec3 centre(0, 0, 1.0);
  const std::vector<Vec3> feet = {{0.5, 0, 0}, {-0.25, 0.43, 0}, {-0.25, -0.43, 0}};
  const std::vector<Vec3> tops = {{0.3, 0, 1.0}, {-0.15, 0.26, 1.0}, {-0.15, -0.26, 1.0}};
  const double D = 0.04;
  Model m;
  m.add_point("C", centre);
  Mat6 expected = Mat6::Zero();
  const double pi = std::numbers::pi, A = pi * D * D / 4, I = pi * std::pow(D, 4) / 64;
  for (int i = 0; i < 3; ++i) {
    const std::string n = std::to_string(i);
    m.add_point("F" + n, feet[i]);
    m.add_point("T" + n, tops[i]);
    m.add_beam("leg" + n, "F" + n, "T" + n, kSteel, Section::circle(D));
    m.add_rigid_link("arm" + n, "C", "T" + n);
    m.add_support("foot" + n, "F" + n, {}, Connection::rigid());
    const double L = (tops[i] - feet[i]).norm();
    const Vec3 x = (tops[i] - feet[i]) / L, y = x.unitOrthogonal(), z = x.cross(y);
    Mat3 R;
    R << x, y, z;
    const Mat6 R6 = reference::rotate6(R);
    const Mat6 leg_compliance =
        R6 * reference::cantilever_compliance(L, kE, kG, A, I, I, 2 * I) * R6.transpose();
    const Mat6 carry = reference::twist_transport(tops[i] - centre);
    expected += carry.transpose() * leg_compliance.inverse() * carry;
  }
  m.add_end_effector("platform", "C", "arm0");
  const Result r = solve(m);
  expect_healthy(r);
  ASSERT_TRUE(r.end_effectors[0].stiffness);
  EXPECT_LT(relative_difference_scaled(*r.end_effectors[0].stiffness, expected), 1e-9);
}

// One leg with a passive spherical joint: free alone, but with the end effector prescribed its
// stiffness is K0 − K0·Jq·(Jqᵀ·K0·Jq)⁻¹·Jqᵀ·K0 (zero in the passive directions).
TEST(Leg, PassiveJointsLeaveStiffnessWithZeroEigenvalues) {
  const Vec3 base(0, 0, 0), knee(0.2, 0.1, 0.6), tip(0.35, 0.1, 0.75);
  const double D = 0.03;
  Model m;
  m.add_point("O", base);
  m.add_point("A", knee);
  m.add_point("E", tip);
  m.add_beam("rod", "O", "A", kSteel, Section::circle(D));
  m.add_rigid_link("stub", "A", "E");
  m.add_support("ground", "O", {}, Connection::rigid());
  m.add_joint("ball", "A", {"rod", "stub"}, Connection::passive(Kinematics::spherical()));
  m.add_end_effector("E", "E");
  const Result r = solve(m);
  ASSERT_TRUE(r.end_effectors[0].stiffness);
  EXPECT_FALSE(r.end_effectors[0].compliance.has_value());
  EXPECT_FALSE(r.end_effectors[0].deflection.has_value());
  EXPECT_FALSE(r.links[0].from.deflection.has_value());
  EXPECT_FALSE(r.report.notes.empty());

  const double L = (knee - base).norm(), pi = std::numbers::pi, A = pi * D * D / 4,
               I = pi * std::pow(D, 4) / 64;
  const Vec3 x = (knee - base) / L, y = x.unitOrthogonal(), z = x.cross(y);
  Mat3 R;
  R << x, y, z;
  const Mat6 R6 = reference::rotate6(R);
  const Mat6 rod =
      R6 * reference::cantilever_compliance(L, kE, kG, A, I, I, 2 * I) * R6.transpose();
  const Mat6 carry = reference::twist_transport(tip - knee);
  const Mat6 K0 = (carry * rod * carry.transpose()).inverse();
  Eigen::Matrix<double, 6, 3> Jq;
  for (int c = 0; c < 3; ++c) Jq.col(c) << Vec3::Unit(c).cross(tip - knee), Vec3::Unit(c);
  const Mat6 expected = K0 - K0 * Jq * (Jq.transpose() * K0 * Jq).inverse() * Jq.transpose() * K0;
  EXPECT_LT(relative_difference(*r.end_effectors[0].stiffness, expected), 1e-9);
}

TEST(Leg, LoadedFreeLegIsAMechanism) {
  Model m;
  m.add_point("O", Vec3::Zero());
  m.add_point("A", Vec3(0, 0, 0.5));
  m.add_point("E", Vec3(0.1, 0, 0.6));
  m.add_beam("rod", "O", "A", kSteel, Section::circle(0.03));
  m.add_rigid_link("stub", "A", "E");
  m.add_support("ground", "O", {}, Connection::rigid());
  m.add_joint("ball", "A", {"rod", "stub"}, Connection::passive(Kinematics::spherical()));
  m.add_load("E", std::nullopt, wrench(10, 0, 0));
  m.add_end_effector("E", "E");
  try {
    solve(m);
    FAIL() << "a loaded mechanism must not solve";
  } catch (const SingularModelError& e) {
    std::string all = e.what();
    for (const auto& d : e.details()) all += "\n" + d;
    EXPECT_NE(all.find("'ball'"), std::string::npos) << all;
    EXPECT_NE(all.find("3 free motions"), std::string::npos) << all;
  }
}

// Springs resist: with W applied to the link, an elastic joint or support must make the
// structure stiffer, and a preload turns the joint the documented way.
TEST(Springs, ElasticJointComplianceIsPositiveAndPreloadTurnsByMinusW0OverK) {
  const double k = 5e4, L = 0.7, w0 = 30;
  Model m;
  m.add_point("O", Vec3::Zero());
  m.add_point("A", Vec3(0.4, 0, 0));
  m.add_point("E", Vec3(0.4 + L, 0, 0));
  m.add_rigid_link("upper", "O", "A");
  m.add_rigid_link("fore", "A", "E");
  m.add_support("ground", "O", {}, Connection::rigid());
  Connection spring = Connection::elastic(Kinematics::revolute(Vec3::UnitZ()), k);
  spring.preload = VecX::Constant(1, w0);
  m.add_joint("elbow", "A", {"upper", "fore"}, spring);
  m.add_end_effector("E", "E");
  const Result r = solve(m);
  expect_healthy(r);
  const Mat6& C = *r.end_effectors[0].compliance;
  EXPECT_NEAR(C(5, 5) * k, 1.0, 1e-12);
  EXPECT_NEAR(C(1, 1) * k / (L * L), 1.0, 1e-12);
  // The joint pushes the first end ("upper") with +w0 and the second with −w0 at q = 0; the
  // free forearm settles where K·q + w0 = 0.
  const auto& q = (*r.joints[0].relative_deflection)[0];
  EXPECT_NEAR(q(0), -w0 / k, 1e-12 * w0 / k);
  EXPECT_NEAR((*r.end_effectors[0].deflection)(5), -w0 / k, 1e-12 * w0 / k);
  EXPECT_NEAR((*r.end_effectors[0].deflection)(1), -L * w0 / k, 1e-12 * L * w0 / k);
}

TEST(Springs, ElasticSupportPreloadTurnsByPlusW0OverK) {
  const double k = 2e4, w0 = -12;
  Model m;
  m.add_point("O", Vec3::Zero());
  m.add_point("E", Vec3(0, 0.5, 0));
  m.add_rigid_link("arm", "O", "E");
  Connection spring = Connection::elastic(Kinematics::revolute(Vec3::UnitX()), k);
  spring.preload = VecX::Constant(1, w0);
  m.add_support("hip", "O", {}, spring);
  m.add_end_effector("E", "E");
  const Result r = solve(m);
  expect_healthy(r);
  EXPECT_NEAR((*r.end_effectors[0].deflection)(3), w0 / k, 1e-12 * std::abs(w0 / k));
  EXPECT_NEAR((*r.end_effectors[0].compliance)(3, 3) * k, 1.0, 1e-12);
  EXPECT_LT(r.supports[0].reaction->norm(), 1e-9);
}

TEST(Actuators, LockedActuatorReportsItsEffort) {
  const double L = 0.6, F = 40;
  Model m;
  m.add_point("O", Vec3::Zero());
  m.add_point("A", Vec3(0, 0, 0.3));
  m.add_point("E", Vec3(L, 0, 0.3));
  m.add_rigid_link("column", "O", "A");
  m.add_rigid_link("arm", "A", "E");
  m.add_support("ground", "O", {}, Connection::rigid());
  m.add_joint("motor", "A", {"column", "arm"},
              Connection::actuated(Kinematics::revolute(Vec3::UnitZ())));
  m.add_load("E", std::nullopt, wrench(0, F, 0));
  m.add_end_effector("E", "E");
  const Result r = solve(m);
  expect_healthy(r);
  ASSERT_TRUE(r.joints[0].effort);
  // The motor holds the arm against the moment L·F about z: it applies +L·F to the column.
  EXPECT_NEAR((*r.joints[0].effort)(0), L * F, 1e-12 * L * F);
  EXPECT_NEAR((*r.joints[0].relative_deflection)[0](0), 0.0, 1e-15);
  EXPECT_LT(relative_difference(*r.supports[0].reaction, wrench(0, -F, 0, 0.3 * F, 0, -L * F)),
            1e-12);
}

// Three beams meeting at a point: the default rigid connection and an explicit rigid joint
// over three ends are the same structure.
TEST(Connections, DefaultRigidConnectionEqualsExplicitThreeEndJoint) {
  auto build = [](bool explicit_joint) {
    Model m;
    m.add_point("O", Vec3::Zero());
    m.add_point("A", Vec3(0, 0, 0.5));
    m.add_point("B", Vec3(0.4, 0, 0.5));
    m.add_point("C", Vec3(0, 0.3, 0.5));
    m.add_beam("post", "O", "A", kSteel, Section::circle(0.04));
    m.add_beam("armB", "A", "B", kSteel, Section::circle(0.03));
    m.add_beam("armC", "A", "C", kSteel, Section::circle(0.03));
    m.add_support("ground", "O", {}, Connection::rigid());
    if (explicit_joint) m.add_joint("weld", "A", {"post", "armB", "armC"}, Connection::rigid());
    m.add_end_effector("B", "B");
    m.add_load("C", std::nullopt, wrench(0, 0, -100));
    return m;
  };
  const Result implicit = solve(build(false)), named = solve(build(true));
  expect_healthy(implicit);
  EXPECT_LT(relative_difference(*named.end_effectors[0].compliance,
                                *implicit.end_effectors[0].compliance),
            1e-13);
  EXPECT_LT(relative_difference(*named.end_effectors[0].deflection,
                                *implicit.end_effectors[0].deflection),
            1e-13);
  ASSERT_TRUE(named.joints[0].relative_deflection);
  EXPECT_EQ(named.joints[0].relative_deflection->size(), 2u);
  // Post and arms: B's compliance is the post's carried to B plus the arm's own.
  const double pi = std::numbers::pi;
  auto props = [&](double D) { return std::pair{pi * D * D / 4, pi * std::pow(D, 4) / 64}; };
  const auto [A4, I4] = props(0.04);
  const auto [A3, I3] = props(0.03);
  Mat3 post_axes, arm_axes;
  post_axes << Vec3::UnitZ(), Vec3::UnitX(), Vec3::UnitY();  // columns: local x, y, z (circular)
  arm_axes << Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ();
  const Mat6 post = reference::rotate6(post_axes) *
                    reference::cantilever_compliance(0.5, kE, kG, A4, I4, I4, 2 * I4) *
                    reference::rotate6(post_axes).transpose();
  const Mat6 arm = reference::cantilever_compliance(0.4, kE, kG, A3, I3, I3, 2 * I3);
  const Mat6 carry = reference::twist_transport(Vec3(0.4, 0, 0));
  EXPECT_LT(relative_difference_scaled(*implicit.end_effectors[0].compliance,
                                       carry * post * carry.transpose() + arm),
            1e-11);
}

TEST(Solvers, EverySolverGivesTheSameCompliance) {
  const Model m = cantilever(50, 1.5, Section::rect(0.03, 0.05));
  const Result base = solve(m);
  for (SolverKind kind : {SolverKind::umfpack, SolverKind::klu}) {
    if (!solver_available(kind)) continue;
    SolveOptions options;
    options.solver = kind;
    const Result other = solve(m, options);
    EXPECT_STREQ(to_string(other.report.solver), to_string(kind));
    EXPECT_LT(relative_difference_scaled(*other.end_effectors[0].compliance,
                                         *base.end_effectors[0].compliance),
              1e-11);
  }
}

// A rigid triangle welded at its corners is a closed rigid loop: its deflections follow the
// flexible post that carries it, while the loop's internal wrenches are not determined.
TEST(OverConstrained, RigidLoopOnAPostFollowsThePostAndLeavesLoopWrenchesNull) {
  const double D = 0.05, L = 0.8;
  const Vec3 a(0, 0, L), b(0.3, 0, L), c(0.1, 0.25, L);
  Model m;
  m.add_point("O", Vec3::Zero());
  m.add_point("A", a);
  m.add_point("B", b);
  m.add_point("C", c);
  m.add_beam("post", "O", "A", kSteel, Section::circle(D));
  m.add_rigid_link("AB", "A", "B");
  m.add_rigid_link("BC", "B", "C");
  m.add_rigid_link("CA", "C", "A");
  m.add_support("ground", "O", {}, Connection::rigid());
  m.add_load("C", "BC", wrench(10, -20, -50, 1, 0, 2));
  m.add_end_effector("C", "C", "BC");
  const Result r = solve(m);
  EXPECT_LT(r.report.relative_residual, 1e-12);
  EXPECT_LT(r.report.equilibrium_error, 1e-11);

  const double pi = std::numbers::pi, A = pi * D * D / 4, I = pi * std::pow(D, 4) / 64;
  Mat3 axes;  // the post's local x along global Z; a circular section makes y, z immaterial
  axes << Vec3::UnitZ(), Vec3::UnitX(), Vec3::UnitY();
  const Mat6 post = reference::rotate6(axes) *
                    reference::cantilever_compliance(L, kE, kG, A, I, I, 2 * I) *
                    reference::rotate6(axes).transpose();
  const Mat6 carry = reference::twist_transport(c - a);
  const Mat6 expected = carry * post * carry.transpose();
  EXPECT_LT(relative_difference_scaled(*r.end_effectors[0].compliance, expected), 1e-11);
  // The post's wrenches and the support reaction are determined by statics.
  const Vec6 load = wrench(10, -20, -50, 1, 0, 2);
  Vec6 moved = load;
  moved.tail<3>() += c.cross(load.head<3>());
  ASSERT_TRUE(r.supports[0].reaction);
  EXPECT_LT(relative_difference(*r.supports[0].reaction, Vec6(-moved)), 1e-11);
  ASSERT_TRUE(r.links[0].from.wrench);
  // Inside the loop every link end wrench is undetermined.
  for (std::size_t l = 1; l < 4; ++l) {
    EXPECT_FALSE(r.links[l].from.wrench.has_value()) << r.links[l].name;
    EXPECT_TRUE(r.links[l].from.deflection.has_value());
  }
  bool noted = false;
  for (const auto& note : r.report.notes)
    noted |= note.find("over-constrained") != std::string::npos;
  EXPECT_TRUE(noted);
}

// A parallelogram of rigid bars and revolute joints (the leg of a Delta or an Orthoglide) both
// sways freely and is over-constrained out of its plane. A beam carries the end effector; with
// the end effector prescribed the sway is stopped by the beam alone:
// K = K_b − K_b·Jq·(Jqᵀ·K_b·Jq)⁻¹·Jqᵀ·K_b, Jq the sway (a pure translation along x).
TEST(OverConstrained, SwayingParallelogramLegStillGivesItsStiffness) {
  const double D = 0.02;
  const Vec3 m_point(0.05, 0.5, 0), tip(0.05, 0.7, 0.1);
  Model m;
  m.add_point("P1", Vec3(0, 0, 0));
  m.add_point("P2", Vec3(0.1, 0, 0));
  m.add_point("Q1", Vec3(0, 0.5, 0));
  m.add_point("Q2", Vec3(0.1, 0.5, 0));
  m.add_point("M", m_point);
  m.add_point("T", tip);
  m.add_rigid_link("bar1", "P1", "Q1");
  m.add_rigid_link("bar2", "P2", "Q2");
  m.add_rigid_link("top1", "Q1", "M");
  m.add_rigid_link("top2", "M", "Q2");
  m.add_beam("finger", "M", "T", kSteel, Section::circle(D));
  const Kinematics hinge = Kinematics::revolute(Vec3::UnitZ());
  m.add_support("S1", "P1", {}, Connection::passive(hinge));
  m.add_support("S2", "P2", {}, Connection::passive(hinge));
  m.add_joint("J1", "Q1", {"bar1", "top1"}, Connection::passive(hinge));
  m.add_joint("J2", "Q2", {"bar2", "top2"}, Connection::passive(hinge));
  m.add_end_effector("T", "T");
  const Result r = solve(m);
  ASSERT_TRUE(r.end_effectors[0].stiffness);
  EXPECT_FALSE(r.end_effectors[0].compliance.has_value());

  const double L = (tip - m_point).norm(), pi = std::numbers::pi, A = pi * D * D / 4,
               I = pi * std::pow(D, 4) / 64;
  const Vec3 x = (tip - m_point) / L, y = x.unitOrthogonal(), z = x.cross(y);
  Mat3 R;
  R << x, y, z;
  const Mat6 R6 = reference::rotate6(R);
  const Mat6 Kb =
      (R6 * reference::cantilever_compliance(L, kE, kG, A, I, I, 2 * I) * R6.transpose()).inverse();
  const Vec6 Jq = Vec6::Unit(0);
  const Mat6 expected = Kb - Kb * Jq * (Jq.transpose() * Kb * Jq).inverse() * Jq.transpose() * Kb;
  EXPECT_LT(relative_difference(*r.end_effectors[0].stiffness, expected), 1e-9);
}

// A strut with ball joints at both ends can spin about its own axis: an idle motion that moves
// no end effector. Refused by default; accepted, the end effector's stiffness is the
// cantilever's plus the strut's axial stiffness EA/L·u·uᵀ.
TEST(IdleMotion, SpinningStrutIsRefusedUnlessAcceptedThenAddsItsAxialStiffness) {
  const double D = 0.04, d = 0.015;
  const Vec3 e(0.8, 0, 0.5), g(0.8, 0.6, 0);
  Model m;
  m.add_point("O", Vec3(0, 0, 0.5));
  m.add_point("E", e);
  m.add_point("G", g);
  m.add_beam("arm", "O", "E", kSteel, Section::circle(D));
  m.add_beam("strut", "G", "E", kSteel, Section::circle(d));
  m.add_support("clamp", "O", {}, Connection::rigid());
  m.add_support("ball_ground", "G", {}, Connection::passive(Kinematics::spherical()));
  m.add_joint("ball_top", "E", {"arm", "strut"}, Connection::passive(Kinematics::spherical()));
  m.add_load("E", "arm", wrench(0, 0, -300));
  m.add_end_effector("tip", "E", "arm");
  try {
    solve(m);
    FAIL() << "an idle motion must be refused by default";
  } catch (const SingularModelError& error) {
    std::string all = error.what();
    for (const auto& line : error.details()) all += "\n" + line;
    EXPECT_NE(all.find("idle"), std::string::npos) << all;
    EXPECT_NE(all.find("'strut'"), std::string::npos) << all;
  }
  SolveOptions options;
  options.accept_idle_motions = true;
  const Result r = solve(m, options);
  EXPECT_LT(r.report.relative_residual, 1e-12);
  EXPECT_LT(r.report.equilibrium_error, 1e-11);
  ASSERT_TRUE(r.end_effectors[0].stiffness);
  const double L = 0.8, pi = std::numbers::pi, A = pi * D * D / 4, I = pi * std::pow(D, 4) / 64;
  const Mat6 arm = reference::cantilever_compliance(L, kE, kG, A, I, I, 2 * I);
  const Vec3 u = (e - g).normalized();
  Mat6 expected = arm.inverse();
  expected.topLeftCorner<3, 3>() += kE * pi * d * d / 4 / (e - g).norm() * u * u.transpose();
  EXPECT_LT(relative_difference(*r.end_effectors[0].stiffness, expected), 1e-9);
  // The strut's end rotations are not determined; the arm's are.
  EXPECT_FALSE(r.links[1].to.deflection.has_value());
  EXPECT_TRUE(r.links[0].to.deflection.has_value());
  // The model file's own option does the same.
  m.options.accept_idle_motions = true;
  EXPECT_LT(relative_difference(*solve(m).end_effectors[0].stiffness, expected), 1e-9);
}

// Two almost collinear hinged bars (a toggle), a near-mechanism: stiff along the bars, nearly
// free across them. A moderate gap solves cleanly; a tiny one is warned about, since no
// floating-point model can resolve a stiffness 1e16 times smaller than its neighbours'.
TEST(IllConditioning, NearMechanismIsWarnedAbout) {
  auto toggle = [](double gap) {
    const double L = 1.0, alpha = std::numbers::pi / 2 - gap;
    Model m;
    m.add_point("left", Vec3(-L * std::sin(alpha), 0, 0));
    m.add_point("right", Vec3(L * std::sin(alpha), 0, 0));
    m.add_point("apex", Vec3(0, 0, L * std::cos(alpha)));
    m.add_beam("bar1", "left", "apex", kSteel, Section::circle(0.03));
    m.add_beam("bar2", "right", "apex", kSteel, Section::circle(0.03));
    const auto hinge = Kinematics::revolute(Vec3::UnitY());
    m.add_support("S1", "left", {}, Connection::passive(hinge));
    m.add_support("S2", "right", {}, Connection::passive(hinge));
    m.add_joint("apex_hinge", "apex", {"bar1", "bar2"}, Connection::passive(hinge));
    m.add_end_effector("apex", "apex", "bar1");
    return m;
  };
  const Result moderate = solve(toggle(1e-3));
  EXPECT_TRUE(moderate.report.warnings.empty());
  const double EA_L = kE * std::numbers::pi * 0.03 * 0.03 / 4, c = std::sin(1e-3);
  EXPECT_NEAR((*moderate.end_effectors[0].compliance)(2, 2) * 2 * EA_L * c * c, 1.0, 1e-9);
  // Stiffness ratio 5e12 between directions: solved, with a warning.
  const Result near = solve(toggle(1e-6));
  ASSERT_FALSE(near.report.warnings.empty());
  EXPECT_NE(near.report.warnings.front().find("near-mechanism"), std::string::npos);
  ASSERT_TRUE(near.end_effectors[0].stiffness);
  // Ratio 5e16: beyond double precision; the stiffness is null with a note that says so.
  const Result beyond = solve(toggle(1e-8));
  EXPECT_FALSE(beyond.end_effectors[0].stiffness.has_value());
  bool noted = false;
  for (const auto& note : beyond.report.notes)
    noted |= note.find("nearly a mechanism") != std::string::npos;
  EXPECT_TRUE(noted);
}

// Above the size of a dense decomposition, singular systems are analysed by sparse QR: a long
// post (150 beam links, 3 600 unknowns and more) still gets its mechanisms named and its
// over-constrained loops solved.
TEST(LargeSingularModels, MechanismIsNamedAndRigidLoopIsSolved) {
  const int segments = 150;
  const double D = 0.05, L = 1.5;
  auto post = [&](Model& m) {
    m.add_point("P0", Vec3::Zero());
    for (int i = 1; i <= segments; ++i) {
      m.add_point("P" + std::to_string(i), Vec3(0, 0, L * i / segments));
      m.add_beam("post" + std::to_string(i), "P" + std::to_string(i - 1), "P" + std::to_string(i),
                 kSteel, Section::circle(D));
    }
    m.add_support("ground", "P0", {}, Connection::rigid());
  };
  const std::string top = "P" + std::to_string(segments), last = "post" + std::to_string(segments);
  {
    Model m;
    post(m);
    m.add_point("E", Vec3(0.2, 0, L));
    m.add_rigid_link("stub", top, "E");
    m.add_joint("ball", top, {last, "stub"}, Connection::passive(Kinematics::spherical()));
    m.add_load("E", std::nullopt, wrench(0, 0, -10));
    m.add_end_effector("E", "E");
    try {
      solve(m);
      FAIL() << "a loaded mechanism must not solve";
    } catch (const SingularModelError& error) {
      std::string all = error.what();
      for (const auto& line : error.details()) all += "\n" + line;
      EXPECT_NE(all.find("'ball'"), std::string::npos) << all;
      EXPECT_NE(all.find("3 free motions"), std::string::npos) << all;
    }
  }
  {
    Model m;
    post(m);
    const Vec3 a(0, 0, L), b(0.3, 0, L), c(0.1, 0.25, L);
    m.add_point("B", b);
    m.add_point("C", c);
    m.add_rigid_link("AB", top, "B");
    m.add_rigid_link("BC", "B", "C");
    m.add_rigid_link("CA", "C", top);
    m.add_end_effector("C", "C", "BC");
    const Result r = solve(m);
    ASSERT_GT(r.system.unknowns, 2400);
    const double pi = std::numbers::pi, A = pi * D * D / 4, I = pi * std::pow(D, 4) / 64;
    Mat3 axes;
    axes << Vec3::UnitZ(), Vec3::UnitX(), Vec3::UnitY();
    const Mat6 column = reference::rotate6(axes) *
                        reference::cantilever_compliance(L, kE, kG, A, I, I, 2 * I) *
                        reference::rotate6(axes).transpose();
    const Mat6 carry = reference::twist_transport(c - a);
    EXPECT_LT(relative_difference_scaled(*r.end_effectors[0].compliance,
                                         carry * column * carry.transpose()),
              1e-10);
    EXPECT_FALSE(r.links[static_cast<std::size_t>(segments)].from.wrench.has_value());
  }
}
