// Loads along links, self-weight and settlements through the whole solve (docs/theory.md §12,
// §13), against textbook reactions, deflections and statics.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>

#include "elements/beam_element.hpp"
#include "stiffmsa/stiffmsa.hpp"

using namespace stiffmsa;

namespace {

constexpr double kTextbook = 1e-9;   // relative: the exact fixed-end method against closed forms
constexpr double kSamePaths = 1e-9;  // two solvers' rounding

constexpr double kE = 2.1e11;
constexpr double kL = 2.0;
const Material kSteel{kE, 0.3, std::nullopt, 7850.0};
// Iy = Iz for the rectangle's square: bending about y and z alike.
const Section kSection = Section::rect(0.04, 0.06);

double iy() { return section_properties(kSection).Iy; }

void expect_relative(double actual, double expected, double tolerance, const std::string& what) {
  EXPECT_NEAR(actual, expected, tolerance * std::abs(expected)) << what;
}

// A beam A–B along x of length kL, split at the points named in `inner` fractions, each part a
// beam "b0", "b1", …; clamped at A ("left") and, if `right`, at B with that connection.
Model beam_along_x(const std::vector<double>& inner, std::optional<Connection> right) {
  Model m;
  std::vector<double> cuts{0.0};
  cuts.insert(cuts.end(), inner.begin(), inner.end());
  cuts.push_back(1.0);
  for (std::size_t i = 0; i < cuts.size(); ++i)
    m.add_point("P" + std::to_string(i), Vec3(cuts[i] * kL, 0, 0));
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
    m.add_beam("b" + std::to_string(i), "P" + std::to_string(i), "P" + std::to_string(i + 1),
               kSteel, kSection);
  m.add_support("left", "P0", {}, Connection::rigid());
  if (right) m.add_support("right", "P" + std::to_string(cuts.size() - 1), {}, *right);
  m.add_end_effector("tip", "P" + std::to_string(cuts.size() - 1));
  return m;
}

// Free to turn about y only: a pin for bending in the x-z plane.
Connection pin() { return Connection::passive(Kinematics::revolute(Vec3::UnitY())); }

Vec6 reaction(const Result& r, const std::string& support) { return *r.support(support).reaction; }

TEST(LinkLoads, FixedFixedUniformLoad) {
  const double q = 3000;
  Model m = beam_along_x({0.5}, Connection::rigid());
  m.add_link_load("b0", DistributedLinkLoad{Vec3(0, 0, -q), Vec3(0, 0, -q)});
  m.add_link_load("b1", DistributedLinkLoad{Vec3(0, 0, -q), Vec3(0, 0, -q)});
  m.add_end_effector("middle", "P1", std::string("b0"));
  const Result r = solve(m);
  const Vec6 left = reaction(r, "left"), right = reaction(r, "right");
  expect_relative(left(2), q * kL / 2, kTextbook, "left Fz");
  expect_relative(right(2), q * kL / 2, kTextbook, "right Fz");
  // The clamps hold the ends level against the sagging span: moments qL²/12 of opposite turn.
  expect_relative(left(4), -q * kL * kL / 12, kTextbook, "left My");
  expect_relative(right(4), q * kL * kL / 12, kTextbook, "right My");
  expect_relative((*r.end_effector("middle").deflection)(2),
                  -q * std::pow(kL, 4) / (384 * kE * iy()), kTextbook, "midspan deflection");
  EXPECT_LT(r.report.equilibrium_error, 1e-12);
}

TEST(LinkLoads, FixedFixedPointLoadOffCentre) {
  const double p = 5000, a = 0.3 * kL, b = kL - a;
  Model m = beam_along_x({}, Connection::rigid());
  m.add_link_load("b0", PointLinkLoad{Vec3(0, 0, -p), Vec3::Zero(), 0.3});
  const Result r = solve(m);
  const Vec6 left = reaction(r, "left"), right = reaction(r, "right");
  expect_relative(left(2), p * b * b * (3 * a + b) / std::pow(kL, 3), kTextbook, "left Fz");
  expect_relative(right(2), p * a * a * (a + 3 * b) / std::pow(kL, 3), kTextbook, "right Fz");
  expect_relative(left(4), -p * a * b * b / (kL * kL), kTextbook, "left My");
  expect_relative(right(4), p * a * a * b / (kL * kL), kTextbook, "right My");
  // The link's end wrenches are the true ones: at the clamps, the reactions.
  const LinkResult& beam = r.link("b0");
  EXPECT_TRUE(beam.from.wrench->isApprox(left, 1e-12));
  EXPECT_TRUE(beam.to.wrench->isApprox(right, 1e-12));
}

TEST(LinkLoads, FixedFixedLinearlyVaryingLoad) {
  const double q = 4000;  // zero at the left end, q at the right
  Model m = beam_along_x({}, Connection::rigid());
  m.add_link_load("b0", DistributedLinkLoad{Vec3::Zero(), Vec3(0, 0, -q)});
  const Result r = solve(m);
  const Vec6 left = reaction(r, "left"), right = reaction(r, "right");
  expect_relative(left(2), 3 * q * kL / 20, kTextbook, "left Fz");
  expect_relative(right(2), 7 * q * kL / 20, kTextbook, "right Fz");
  expect_relative(left(4), -q * kL * kL / 30, kTextbook, "left My");
  expect_relative(right(4), q * kL * kL / 20, kTextbook, "right My");
}

TEST(LinkLoads, ProppedCantileverUniformLoad) {
  const double q = 2500;
  Model m = beam_along_x({}, pin());
  m.add_link_load("b0", DistributedLinkLoad{Vec3(0, 0, -q), Vec3(0, 0, -q)});
  const Result r = solve(m);
  const Vec6 left = reaction(r, "left"), right = reaction(r, "right");
  expect_relative(left(2), 5 * q * kL / 8, kTextbook, "clamp Fz");
  expect_relative(right(2), 3 * q * kL / 8, kTextbook, "prop Fz");
  expect_relative(left(4), -q * kL * kL / 8, kTextbook, "clamp My");
  EXPECT_NEAR(right(4), 0, 1e-9 * q * kL * kL);
  // The pinned end turns by qL³/(48EI), rising toward it (w' > 0, θy = −w').
  expect_relative((*r.link("b0").to.deflection)(4), -q * std::pow(kL, 3) / (48 * kE * iy()),
                  kTextbook, "prop rotation");
}

TEST(LinkLoads, ProppedCantileverPointLoadAtMidspan) {
  const double p = 8000;
  Model m = beam_along_x({}, pin());
  m.add_link_load("b0", PointLinkLoad{Vec3(0, 0, -p), Vec3::Zero(), 0.5});
  const Result r = solve(m);
  expect_relative(reaction(r, "left")(2), 11 * p / 16, kTextbook, "clamp Fz");
  expect_relative(reaction(r, "right")(2), 5 * p / 16, kTextbook, "prop Fz");
  expect_relative(reaction(r, "left")(4), -3 * p * kL / 16, kTextbook, "clamp My");
}

TEST(LinkLoads, CantileverUnderItsOwnWeight) {
  Model m = beam_along_x({}, std::nullopt);
  m.gravity = Vec3(0, 0, -9.81);
  const Result r = solve(m);
  const double w = 7850 * section_properties(kSection).A * 9.81;
  expect_relative((*r.end_effector("tip").deflection)(2), -w * std::pow(kL, 4) / (8 * kE * iy()),
                  kTextbook, "tip deflection wL⁴/8EI");
  expect_relative((*r.end_effector("tip").deflection)(4), w * std::pow(kL, 3) / (6 * kE * iy()),
                  kTextbook, "tip rotation wL³/6EI");
  const Vec6 base = reaction(r, "left");
  expect_relative(base(2), w * kL, kTextbook, "reaction = weight");
  expect_relative(base(4), -w * kL * kL / 2, kTextbook, "clamp moment");
}

// Internal forces at every station against the statics of the part beyond it.
TEST(LinkLoads, InternalForcesAgainstStatics) {
  const double q = 1200, p = 700, position = 0.35;
  Model m = beam_along_x({}, std::nullopt);
  m.add_link_load("b0", DistributedLinkLoad{Vec3(0, 200, -q), Vec3(0, 200, -q)});
  m.add_link_load("b0", PointLinkLoad{Vec3(50, 0, -p), Vec3(0, 0, 30), position});
  const Result r = solve(m);
  const auto& stations = r.link("b0").internal_forces;
  ASSERT_EQ(stations.size(), 12u);  // 11 evenly spaced and the point load's
  const Mat3 axes = detail::link_axes(Vec3::Zero(), Vec3(kL, 0, 0), std::nullopt);
  for (const InternalForces& s : stations) {
    const double x = s.position * kL;
    // The part beyond the station carries the loads on it; it exerts on the part before the
    // negative of what holds it, i.e. the loads beyond, about the cut.
    Vec3 force = Vec3(0, 200, -q) * (kL - x);
    Vec3 moment = Vec3((kL + x) / 2 - x, 0, 0).cross(Vec3(0, 200, -q) * (kL - x));
    if (position * kL >= x) {  // the value at the point load's station is the from side's limit
      force += Vec3(50, 0, -p);
      moment += Vec3(0, 0, 30) + Vec3(position * kL - x, 0, 0).cross(Vec3(50, 0, -p));
    }
    const Vec3 local_force = axes * force, local_moment = axes * moment;
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(s.forces(i), local_force(i), 1e-9 * q * kL) << "station " << s.position;
      EXPECT_NEAR(s.forces(3 + i), local_moment(i), 1e-9 * q * kL * kL) << "station " << s.position;
    }
  }
}

TEST(LinkLoads, RigidLinkCarriesItsLoadsResultant) {
  Model m;
  m.add_point("A", Vec3::Zero());
  m.add_point("B", Vec3(1, 0, 0));
  m.add_point("C", Vec3(2, 0, 0));
  m.add_beam("beam", "A", "B", kSteel, kSection);
  m.add_rigid_link("arm", "B", "C");
  m.add_support("ground", "A", {}, Connection::rigid());
  m.add_end_effector("tip", "C");
  // 400 N/m on the rigid arm is 400 N at its middle: the same as that point load.
  Model point = m;
  m.add_link_load("arm", DistributedLinkLoad{Vec3(0, 0, -400), Vec3(0, 0, -400)});
  point.add_load("B", std::string("arm"), (Vec6() << 0, 0, -400, 0, 200, 0).finished());
  const Result r = solve(m), expected = solve(point);
  EXPECT_TRUE(
      r.end_effector("tip").deflection->isApprox(*expected.end_effector("tip").deflection, 1e-12));
  EXPECT_TRUE(reaction(r, "ground").isApprox(reaction(expected, "ground"), 1e-12));
  EXPECT_LT(r.report.equilibrium_error, 1e-12);
}

TEST(Settlements, FixedFixedBeamEndSettlement) {
  const double delta = 0.002;
  Model m = beam_along_x({}, Connection::rigid());
  m.support(SupportIndex{1}).displacement = (Vec6() << 0, 0, -delta, 0, 0, 0).finished();
  const Result r = solve(m);
  const double ei = kE * iy();
  const Vec6 left = reaction(r, "left"), right = reaction(r, "right");
  // The settling end pulls the beam down there and the far clamp holds it up.
  expect_relative(left(2), 12 * ei * delta / std::pow(kL, 3), kTextbook, "left shear");
  expect_relative(right(2), -12 * ei * delta / std::pow(kL, 3), kTextbook, "right shear");
  expect_relative(std::abs(left(4)), 6 * ei * delta / (kL * kL), kTextbook, "left moment");
  expect_relative(std::abs(right(4)), 6 * ei * delta / (kL * kL), kTextbook, "right moment");
  EXPECT_NEAR((*r.end_effector("tip").deflection)(2), -delta, 1e-15);
}

TEST(Settlements, TwoSpanContinuousBeamMiddleSupportSettles) {
  const double delta = 0.001;
  Model m;
  m.add_point("A", Vec3::Zero());
  m.add_point("B", Vec3(kL, 0, 0));
  m.add_point("C", Vec3(2 * kL, 0, 0));
  m.add_beam("AB", "A", "B", kSteel, kSection);
  m.add_beam("BC", "B", "C", kSteel, kSection);
  // Pins about y; A also holds the axial direction and the torsion, which nothing else would.
  m.add_support("A", "A", {}, pin());
  m.add_support("B", "B", {}, pin());
  m.add_support("C", "C", {}, pin());
  m.support(SupportIndex{1}).displacement = (Vec6() << 0, 0, -delta, 0, 0, 0).finished();
  m.add_end_effector("middle", "B", std::string("AB"));
  const Result r = solve(m);
  const double ei = kE * iy();
  // The simply supported span 2L pulled down by R at its middle: R·(2L)³/(48EI) = Δ.
  const double pull = 6 * ei * delta / std::pow(kL, 3);
  expect_relative(reaction(r, "B")(2), -pull, kTextbook, "middle reaction");
  expect_relative(reaction(r, "A")(2), pull / 2, kTextbook, "end reaction A");
  expect_relative(reaction(r, "C")(2), pull / 2, kTextbook, "end reaction C");
  EXPECT_NEAR((*r.end_effector("middle").deflection)(2), -delta, 1e-15);
  EXPECT_LT(r.report.equilibrium_error, 1e-12);
}

TEST(Settlements, AlongAFreeDirectionIsRefused) {
  Model m = beam_along_x({}, pin());
  m.support(SupportIndex{1}).displacement = (Vec6() << 0, 0, 0, 0, 0.01, 0).finished();
  EXPECT_THROW(solve(m), InputError);
}

// The tree solve, the frame solve and the sparse LU give the same results of every case.
void expect_same_results(const Result& a, const Result& b) {
  ASSERT_EQ(a.load_cases.size(), b.load_cases.size());
  for (std::size_t l = 0; l < a.links.size(); ++l) {
    for (const auto end : {&LinkResult::from, &LinkResult::to}) {
      const LinkEndResult &x = a.links[l].*end, &y = b.links[l].*end;
      const double d = x.deflection->norm(), w = x.wrench->norm();
      EXPECT_LT((*x.deflection - *y.deflection).norm(), kSamePaths * d + 1e-18) << a.links[l].name;
      EXPECT_LT((*x.wrench - *y.wrench).norm(), kSamePaths * w + 1e-9) << a.links[l].name;
    }
  }
  for (std::size_t e = 0; e < a.end_effectors.size(); ++e)
    EXPECT_TRUE(
        a.end_effectors[e].compliance->isApprox(*b.end_effectors[e].compliance, kSamePaths));
  for (std::size_t c = 0; c < a.load_cases.size(); ++c)
    expect_same_results(a.load_cases[c], b.load_cases[c]);
}

TEST(SolvePaths, TreeAndSparseAgreeWithLinkLoadsCasesAndSettlement) {
  Model m = beam_along_x({0.4}, std::nullopt);
  m.add_link_load("b0", DistributedLinkLoad{Vec3(0, 100, -300), Vec3(0, 0, -900)});
  m.support(SupportIndex{0}).displacement = (Vec6() << 0.001, 0, -0.002, 0.001, 0, 0).finished();
  LoadCase point{"point", {}, {}, std::nullopt, {}};
  point.link_loads.push_back({"b1", PointLinkLoad{Vec3(0, 0, -500), Vec3(10, 0, 0), 0.6}, {}});
  m.add_load_case(point);
  LoadCase weight{"weight", {}, {}, Vec3(0, 0, -9.81), {}};
  m.add_load_case(weight);
  const Result tree = solve(m);
  EXPECT_EQ(tree.report.solver, SolverUsed::tree);
  SolveOptions sparse;
  sparse.solver = SolverKind::sparse_lu;
  const Result lu = solve(m, sparse);
  EXPECT_EQ(lu.report.solver, SolverUsed::sparse_lu);
  expect_same_results(tree, lu);
}

// A closed square of steel beams (one corner raised), clamped at P0.
Model closed_square_on_a_clamp() {
  Model m;
  const std::array<Vec3, 4> corners = {Vec3(0, 0, 0), Vec3(kL, 0, 0), Vec3(kL, kL, 0),
                                       Vec3(0, kL, 0.3)};
  for (int i = 0; i < 4; ++i) m.add_point("P" + std::to_string(i), corners[i]);
  for (int i = 0; i < 4; ++i)
    m.add_beam("b" + std::to_string(i), "P" + std::to_string(i), "P" + std::to_string((i + 1) % 4),
               kSteel, kSection);
  m.add_support("left", "P0", {}, Connection::rigid());
  return m;
}

// A closed square of beams on one clamp: a loop not through the ground, which the frame solve
// takes.
TEST(SolvePaths, FrameAndSparseAgreeWithLinkLoads) {
  Model m = closed_square_on_a_clamp();
  m.add_end_effector("tip", "P2", std::string("b1"));
  m.add_link_load("b1", DistributedLinkLoad{Vec3(0, 300, -300), Vec3(0, 0, -900)});
  m.add_link_load("b2", PointLinkLoad{Vec3(0, 40, -500), Vec3(10, 0, 0), 0.2});
  LoadCase weight{"weight", {}, {}, Vec3(0, 0, -9.81), {}};
  m.add_load_case(weight);
  const Result frame = solve(m);
  EXPECT_EQ(frame.report.solver, SolverUsed::frame);
  SolveOptions sparse;
  sparse.solver = SolverKind::sparse_lu;
  expect_same_results(frame, solve(m, sparse));
}

// A frame whose support settles: the frame solve moves the settled ends by d and loads the
// nodes with −K·d, as the sparse LU of the whole system does.
TEST(SolvePaths, FrameAndSparseAgreeWithASettlement) {
  Model m = closed_square_on_a_clamp();
  m.add_support("far", "P2", {}, Connection::rigid());
  m.support(SupportIndex{1}).displacement = (Vec6() << 0.0005, 0, -0.001, 0, 0.0002, 0).finished();
  m.add_end_effector("corner", "P1", std::string("b0"));
  m.add_link_load("b0", DistributedLinkLoad{Vec3(0, 0, -400), Vec3(0, 0, -400)});
  LoadCase point{"point", {}, {}, std::nullopt, {}};
  point.link_loads.push_back({"b3", PointLinkLoad{Vec3(0, 0, -500), Vec3(10, 0, 0), 0.6}, {}});
  m.add_load_case(point);
  const Result frame = solve(m);
  EXPECT_EQ(frame.report.solver, SolverUsed::frame);
  SolveOptions sparse;
  sparse.solver = SolverKind::sparse_lu;
  expect_same_results(frame, solve(m, sparse));
  EXPECT_TRUE(
      frame.link("b1").to.deflection->isApprox(*m.support(SupportIndex{1}).displacement, 1e-15));
  EXPECT_LT(frame.report.equilibrium_error, 1e-12);
}

}  // namespace
