// Results must not depend on where the model sits or how it is turned, nor on which of the
// equivalent link descriptions (beam, 12×12 matrix, 6×6 compliance) the user chose.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "builders.hpp"
#include "closed_forms.hpp"
#include "stiffmsa/stiffmsa.hpp"

using namespace stiffmsa;

namespace {

const Material kAluminium{7.0e10, 0.33, std::nullopt};

// A spatial arm with every element kind: beams with explicit zref, a matrix-free rigid link,
// elastic, passive (with a stiff return spring) and preloaded joints, a load and an elastic
// support.
Model spatial_arm() {
  Model m;
  m.add_point("O", Vec3(0, 0, 0));
  m.add_point("A", Vec3(0.1, 0.0, 0.5));
  m.add_point("B", Vec3(0.6, 0.2, 0.6));
  m.add_point("C", Vec3(0.9, 0.1, 0.4));
  m.add_point("E", Vec3(1.0, 0.15, 0.3));
  Link& column = m.link(m.add_beam("column", "O", "A", kAluminium, Section::rect(0.08, 0.12)));
  std::get<BeamLink>(column.kind).zref = Vec3(1, 0.2, 0);
  Link& upper =
      m.link(m.add_beam("upper", "A", "B", kAluminium, Section::rect_tube(0.06, 0.1, 0.005)));
  std::get<BeamLink>(upper.kind).zref = Vec3(0, 0.3, 1);
  std::get<BeamLink>(upper.kind).shear = true;
  Link& fore = m.link(m.add_beam("fore", "B", "C", kAluminium, Section::tube(0.05, 0.004)));
  std::get<BeamLink>(fore.kind).zref = Vec3(0, 0, 1);
  m.add_rigid_link("wrist", "C", "E");
  const Connection base = Connection::elastic(Kinematics::revolute(Vec3(0, 0, 1)), 4e5);
  m.add_support("base", "O", {}, base);
  m.add_joint("shoulder", "A", {"column", "upper"},
              Connection::elastic(Kinematics::universal(Vec3(0, 1, 0), Vec3(1, 0, 0.2)),
                                  MatX(Eigen::Vector2d(3e5, 2e5).asDiagonal()))
                  .preloaded(VecX::Constant(2, 4.0)));
  m.add_joint("elbow", "B", {"upper", "fore"},
              Connection::actuated(Kinematics::revolute(Vec3(0.1, 1, 0)), 1.5e5));
  m.add_load("E", std::nullopt, stiffmsa::testing::wrench(15, -20, -60, 1, 2, -3));
  m.add_end_effector("tool", "E");
  m.add_end_effector("elbow", "B", "fore");
  return m;
}

// Moves every point by p after turning it by R; turns every direction and given matrix.
Model transformed(Model m, const Mat3& R, const Vec3& p) {
  const Mat6 R6 = reference::rotate6(R);
  for (auto& point : m.points) point.position = R * point.position + p;
  for (auto& link : m.links)
    if (auto* beam = std::get_if<BeamLink>(&link.kind); beam && beam->zref)
      beam->zref = R * *beam->zref;
  auto turn = [&](Kinematics& k) {
    k.axis = R * k.axis;
    k.axis_b = R * k.axis_b;
    k.normal = R * k.normal;
    for (auto& row : k.free_rows) row = R6 * row;
  };
  for (auto& j : m.joints) turn(j.connection.kinematics);
  for (auto& s : m.supports) turn(s.connection.kinematics);
  for (auto& load : m.loads) load.wrench = R6 * load.wrench;
  return m;
}

}  // namespace

TEST(Invariance, TurnedAndMovedModelGivesTurnedResults) {
  const Model original = spatial_arm();
  const Result a = solve(original);
  ASSERT_LT(a.report.relative_residual, 1e-12);
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  const Vec3 p(3.0, -1.5, 2.0);
  const Result b = solve(transformed(original, R, p));
  const Mat6 R6 = reference::rotate6(R);
  for (std::size_t e = 0; e < a.end_effectors.size(); ++e) {
    const Mat6 turned_back = R6.transpose() * *b.end_effectors[e].compliance * R6;
    EXPECT_LT(reference::relative_difference_scaled(turned_back, *a.end_effectors[e].compliance),
              1e-10);
    const Vec6 deflection_back = R6.transpose() * *b.end_effectors[e].deflection;
    EXPECT_LT(reference::relative_difference(deflection_back, *a.end_effectors[e].deflection),
              1e-10);
  }
  // Joint deflections are along the joints' own directions: unchanged.
  for (std::size_t j = 0; j < a.joints.size(); ++j)
    EXPECT_LT(reference::relative_difference((*b.joints[j].relative_deflection)[0],
                                             (*a.joints[j].relative_deflection)[0]),
              1e-10);
  // The support reaction turns with the model (moment about the moved point).
  EXPECT_LT(reference::relative_difference(Vec6(R6.transpose() * *b.supports[0].reaction),
                                           *a.supports[0].reaction),
            1e-10);
}

TEST(Invariance, BeamMatrixAndComplianceLinksAgree) {
  const Vec3 from(0.2, 0.1, 0.0), to(0.9, 0.5, 0.4);
  const Vec3 zref(0, 0, 1);
  const Section section = Section::rect(0.05, 0.08);
  // The same link three ways; the matrices are written from textbook formulas in local axes.
  const SectionProperties s = section_properties(section);
  const double L = (to - from).norm(), G = shear_modulus(kAluminium);
  const Mat6 local_compliance =
      reference::cantilever_compliance(L, kAluminium.E, G, s.A, s.Iy, s.Iz, s.J);
  const Mat6 K = local_compliance.inverse();
  Mat6 D = Mat6::Identity();  // transports a rigid motion from `from` to `to` along local x
  D.block<3, 3>(0, 3) = -reference::cross_matrix(Vec3(L, 0, 0));
  Mat12 local_stiffness;
  local_stiffness << D.transpose() * K * D, -D.transpose() * K, -K * D, K;

  auto build = [&](int kind) {
    Model m;
    m.add_point("P", from);
    m.add_point("Q", to);
    m.add_point("T", to + Vec3(0.1, -0.2, 0.05));
    if (kind == 0) {
      Link& l = m.link(m.add_beam("link", "P", "Q", kAluminium, section));
      std::get<BeamLink>(l.kind).zref = zref;
    } else if (kind == 1) {
      Link& l = m.link(m.add_matrix_link("link", "P", "Q", local_stiffness, LinkFrame::local));
      std::get<MatrixLink>(l.kind).zref = zref;
    } else {
      Link& l = m.link(m.add_compliance_link("link", "P", "Q", local_compliance, LinkFrame::local));
      std::get<ComplianceLink>(l.kind).zref = zref;
    }
    m.add_rigid_link("tool", "Q", "T");
    m.add_support("clamp", "P", {}, Connection::rigid());
    m.add_end_effector("T", "T");
    m.add_load("T", std::nullopt, stiffmsa::testing::wrench(5, 10, -30, 0, 1, 0));
    return m;
  };
  const Result beam = solve(build(0)), matrix = solve(build(1)), compliance = solve(build(2));
  for (const Result* other : {&matrix, &compliance}) {
    EXPECT_LT(reference::relative_difference_scaled(*other->end_effectors[0].compliance,
                                                    *beam.end_effectors[0].compliance),
              1e-10);
    EXPECT_LT(reference::relative_difference(*other->links[0].to.wrench, *beam.links[0].to.wrench),
              1e-10);
    EXPECT_LT(reference::relative_difference(*other->end_effectors[0].deflection,
                                             *beam.end_effectors[0].deflection),
              1e-10);
  }
}
