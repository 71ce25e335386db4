// Load cases solved with one factorisation (docs/theory.md §13): each case's results equal a
// separate solve of the model with that case's loads alone, the cases superpose, and the robot's
// self-weight column gives what a second solve of the weight alone gave.
#include <gtest/gtest.h>

#include <string>

#include "builders.hpp"
#include "stiffmsa/io/model_file.hpp"
#include "stiffmsa/stiffmsa.hpp"

using namespace stiffmsa;
using stiffmsa::testing::wrench;

namespace {

constexpr double kSameSolve = 1e-12;  // relative: one factorisation against another's rounding

void expect_close(const std::optional<Vec6>& a, const std::optional<Vec6>& b, double scale,
                  const std::string& what) {
  ASSERT_EQ(a.has_value(), b.has_value()) << what;
  if (!a) return;
  EXPECT_LE((*a - *b).norm(), kSameSolve * scale) << what << "\n"
                                                  << a->transpose() << "\n"
                                                  << b->transpose();
}

double largest_deflection(const Result& r) {
  double largest = 0;
  for (const auto& l : r.links)
    for (const auto* e : {&l.from, &l.to})
      if (e->deflection) largest = std::max(largest, e->deflection->norm());
  return largest;
}

double largest_wrench(const Result& r) {
  double largest = 0;
  for (const auto& l : r.links)
    for (const auto* e : {&l.from, &l.to})
      if (e->wrench) largest = std::max(largest, e->wrench->norm());
  return largest;
}

// Every state result of `a` against `b`'s.
void expect_same_state(const Result& a, const Result& b) {
  const double d = largest_deflection(b), w = largest_wrench(b);
  for (std::size_t l = 0; l < a.links.size(); ++l) {
    expect_close(a.links[l].from.deflection, b.links[l].from.deflection, d, a.links[l].name);
    expect_close(a.links[l].to.deflection, b.links[l].to.deflection, d, a.links[l].name);
    expect_close(a.links[l].from.wrench, b.links[l].from.wrench, w, a.links[l].name);
    expect_close(a.links[l].to.wrench, b.links[l].to.wrench, w, a.links[l].name);
    // A model loaded along links anywhere gives every case's internal forces; the separate
    // solve of a case without such loads gives none.
    if (b.links[l].internal_forces.empty()) continue;
    ASSERT_EQ(a.links[l].internal_forces.size(), b.links[l].internal_forces.size());
    for (std::size_t s = 0; s < a.links[l].internal_forces.size(); ++s)
      EXPECT_LE(
          (a.links[l].internal_forces[s].forces - b.links[l].internal_forces[s].forces).norm(),
          kSameSolve * w);
  }
  for (std::size_t j = 0; j < a.joints.size(); ++j)
    expect_close(a.joints[j].wrench, b.joints[j].wrench, w, a.joints[j].name);
  for (std::size_t s = 0; s < a.supports.size(); ++s)
    expect_close(a.supports[s].reaction, b.supports[s].reaction, w, a.supports[s].name);
  for (std::size_t e = 0; e < a.end_effectors.size(); ++e) {
    expect_close(a.end_effectors[e].deflection, b.end_effectors[e].deflection, d,
                 a.end_effectors[e].name);
    EXPECT_TRUE(
        a.end_effectors[e].compliance->isApprox(*b.end_effectors[e].compliance, kSameSolve));
  }
}

// The arm of builders.hpp with a beam's loads along it; `loads` chooses which.
Model arm_with(int loads) {
  Model m = stiffmsa::testing::two_joint_arm(0.4, 2e4);
  m.loads.clear();
  if (loads & 1) m.add_load("E", std::nullopt, wrench(30, 0, -200, 0, 5, 0));
  if (loads & 2) m.add_link_load("upper", DistributedLinkLoad{Vec3(0, 0, -300), Vec3(20, 0, -600)});
  if (loads & 4) m.add_link_load("column", PointLinkLoad{Vec3(100, -50, 0), Vec3(0, 0, 8), 0.7});
  return m;
}

LoadCase case_of(const std::string& name, const Model& loaded) {
  return LoadCase{name, loaded.loads, loaded.link_loads, loaded.gravity, {}};
}

TEST(LoadCases, EachCaseEqualsASeparateSolve) {
  Model m = arm_with(1);  // the unnamed case: the tip load
  m.add_load_case(case_of("beam", arm_with(2)));
  m.add_load_case(case_of("point", arm_with(4)));
  m.add_load_case(case_of("all", arm_with(7)));
  for (const SolverKind solver : {SolverKind::automatic, SolverKind::sparse_lu}) {
    SolveOptions options;
    options.solver = solver;
    const Result r = solve(m, options);
    ASSERT_EQ(r.load_cases.size(), 3u);
    EXPECT_EQ(r.load_case, "");
    expect_same_state(r, solve(arm_with(1), options));
    const int loads[] = {2, 4, 7};
    for (std::size_t c = 0; c < 3; ++c) {
      SCOPED_TRACE(r.load_cases[c].load_case);
      EXPECT_TRUE(r.load_cases[c].load_cases.empty());
      expect_same_state(r.load_cases[c], solve(arm_with(loads[c]), options));
      EXPECT_LT(r.load_cases[c].report.equilibrium_error, 1e-12);
    }
    EXPECT_EQ(&r.load_case_result("point"), &r.load_cases[1]);
  }
}

TEST(LoadCases, CasesSuperpose) {
  Model m = arm_with(0);
  m.add_load_case(case_of("tip", arm_with(1)));
  m.add_load_case(case_of("beam", arm_with(2)));
  m.add_load_case(case_of("point", arm_with(4)));
  m.add_load_case(case_of("all", arm_with(7)));
  const Result r = solve(m);
  // No unnamed case: the top level is the first named case's.
  EXPECT_EQ(r.load_case, "tip");
  ASSERT_EQ(r.load_cases.size(), 4u);
  const Result &tip = r.load_cases[0], &beam = r.load_cases[1], &point = r.load_cases[2],
               &all = r.load_cases[3];
  expect_same_state(r, tip);
  const double w = largest_wrench(all);
  for (std::size_t l = 0; l < all.links.size(); ++l)
    EXPECT_LE((*all.links[l].from.wrench - (*tip.links[l].from.wrench + *beam.links[l].from.wrench +
                                            *point.links[l].from.wrench))
                  .norm(),
              kSameSolve * w);
  const Vec6 sum = *tip.end_effectors[0].deflection + *beam.end_effectors[0].deflection +
                   *point.end_effectors[0].deflection;
  EXPECT_LE((*all.end_effectors[0].deflection - sum).norm(),
            kSameSolve * all.end_effectors[0].deflection->norm());
}

// The robot's deflection under its self-weight, now one more column of the same solve, against
// the weight alone solved on its own (its other loads and preloads at zero).
TEST(LoadCases, RobotSelfWeightColumnEqualsASeparateSolve) {
  for (const char* file : {"seven-axis.yaml"}) {  // the example robot with its weight
    SCOPED_TRACE(file);
    const Model robot =
        load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/robots/" + std::string(file));
    Model weight = robot;
    bool any = false;
    for (Load& l : weight.loads) {
      any |= l.self_weight;
      if (!l.self_weight) l.wrench.setZero();
    }
    ASSERT_TRUE(any);
    for (Joint& j : weight.joints)
      if (j.connection.preload) j.connection.preload->setZero();
    const Result r = solve(robot), alone = solve(weight);
    for (std::size_t e = 0; e < r.end_effectors.size(); ++e) {
      const Vec6 expected = *alone.end_effectors[e].deflection;
      ASSERT_TRUE(r.end_effectors[e].deflection_gravity.has_value());
      EXPECT_LE((*r.end_effectors[e].deflection_gravity - expected).norm(),
                1e-14 * expected.norm() + 1e-300);
    }
  }
}

TEST(LoadCases, UnknownCaseNameIsANameError) {
  Model m = arm_with(1);
  m.add_load_case(case_of("beam", arm_with(2)));
  const Result r = solve(m);
  EXPECT_THROW(r.load_case_result("bean"), NameError);
}

}  // namespace
