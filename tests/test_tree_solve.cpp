// The tree solve against the factorising solve of the same system: models whose links and
// connections form a tree on one support are solved by `auto` without factorising
// (solver/tree_solver.hpp); every number they report must be the one the factorised mixed
// system gives.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>
#include <string>

#include "assembly/topology.hpp"
#include "builders.hpp"
#include "solve_comparison.hpp"
#include "solver/tree_solver.hpp"
#include "stiffmsa/stiffmsa.hpp"

using namespace stiffmsa;
using namespace stiffmsa::testing;

namespace {

const Material kSteel{2.1e11, 0.3, std::nullopt};

// A branched arm with every element a tree solve passes: an elastic, preloaded support; a rigid
// joint of three link ends; elastic joints (one preloaded, one of two directions); beams,
// rigid links and a CAD compliance link; loads on both branches and on a loose end; two end
// effectors.
Model branched_arm() {
  Model m;
  m.add_point("base", Vec3(0, 0, 0));
  m.add_point("hub", Vec3(0.05, 0.02, 0.6));
  m.add_point("elbow_a", Vec3(0.45, 0.1, 0.7));
  m.add_point("tip_a", Vec3(0.8, 0.05, 0.55));
  m.add_point("elbow_b", Vec3(-0.3, 0.35, 0.75));
  m.add_point("tip_b", Vec3(-0.5, 0.6, 0.5));
  m.add_point("stub", Vec3(0.1, -0.3, 0.65));
  m.add_beam("column", "base", "hub", kSteel, Section::tube(0.12, 0.008));
  m.add_beam("upper_a", "hub", "elbow_a", kSteel, Section::rect_tube(0.08, 0.1, 0.005));
  std::get<BeamLink>(
      m.link(m.add_beam("fore_a", "elbow_a", "tip_a", kSteel, Section::circle(0.04))).kind)
      .shear = true;
  m.add_rigid_link("upper_b", "hub", "elbow_b");
  Mat6 c = Mat6::Identity() * 2e-7;
  c(0, 4) = c(4, 0) = 3e-8;
  m.add_compliance_link("fore_b", "elbow_b", "tip_b", c);
  m.add_beam("bracket", "hub", "stub", kSteel, Section::rect(0.03, 0.05));

  MatX hip_k(3, 3);
  hip_k << 8e6, 2e5, 0, 2e5, 6e6, 1e5, 0, 1e5, 9e6;
  const Connection hip =
      Connection::elastic(Kinematics::spherical(), hip_k).preloaded(VecX::Constant(3, 15.0));
  m.add_support("ground", "base", {}, hip);
  m.add_joint("hub", "hub", {"column", "upper_a", "upper_b", "bracket"}, Connection::rigid());
  const Connection elbow_a =
      Connection::elastic(Kinematics::revolute(Vec3(0, 1, 0.2)), 4e4).preloaded(-3.0);
  m.add_joint("elbow_a", "elbow_a", {"upper_a", "fore_a"}, elbow_a);
  MatX wrist_k(2, 2);
  wrist_k << 2e4, 5e2, 5e2, 3e4;
  const Connection elbow_b =
      Connection::elastic(Kinematics::universal(Vec3(1, 0, 0), Vec3(0, 0.6, 0.8)), wrist_k);
  m.add_joint("elbow_b", "elbow_b", {"fore_b", "upper_b"}, elbow_b);  // end 1 is the outer link
  m.add_load("tip_a", std::nullopt, stiffmsa::testing::wrench(10, -40, -120, 2, 0, 1));
  m.add_load("tip_b", std::nullopt, stiffmsa::testing::wrench(-5, 20, -60, 0, 3, 0));
  m.add_load("stub", std::nullopt, stiffmsa::testing::wrench(0, 0, -30, 0, 0, 0));
  m.add_end_effector("a", "tip_a");
  m.add_end_effector("b", "tip_b");
  return m;
}

}  // namespace

TEST(TreeSolve, ExamplesThatAreTreesMatchTheFactorisedSolve) {
  std::set<std::string> solved_on_tree, cut;
  for (const char* file : {"cantilever.yaml", "planar-2r.yaml", "industrial-6axis.yaml",
                           "planar-3rpr.yaml", "gough-stewart-6ups.yaml", "tripteron.yaml"}) {
    const Model m = load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/" + file);
    const Result automatic = solve(m);
    if (automatic.report.solver == stiffmsa::SolverUsed::tree) solved_on_tree.insert(file);
    if (automatic.report.solver == stiffmsa::SolverUsed::tree_with_cuts) cut.insert(file);
    SolveOptions factorising;
    factorising.solver = factorising_solver();
    SCOPED_TRACE(file);
    expect_same_results(automatic, solve(m, factorising), 1e-13);
  }
  // The serial ones as they are; the parallel robots' legs meet at the platform and close their
  // loops through the ground, with passive joints: cut at their second supports and free motions
  // (16 cut unknowns for the 3-RPR: a passive root hinge, two supports' reactions, three passive
  // hinges; 21 for the tripteron: the reactions of supports screw_y and screw_z, nine passive
  // hinges). The Gough–Stewart platform would have
  // 50, beyond kMostCutUnknowns: factorised.
  EXPECT_EQ(solved_on_tree,
            (std::set<std::string>{"cantilever.yaml", "planar-2r.yaml", "industrial-6axis.yaml"}));
  EXPECT_EQ(cut, (std::set<std::string>{"planar-3rpr.yaml", "tripteron.yaml"}));
  for (const auto& [file, cut_unknowns] :
       {std::pair<const char*, detail::Index>{"planar-3rpr.yaml", 16},
        std::pair<const char*, detail::Index>{"tripteron.yaml", 21}}) {
    const Model m = load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/" + file);
    const detail::Topology topology = detail::build_topology(m);
    detail::TreeScratch scratch;
    const auto solved_cuts = detail::tree_solve(detail::make_blocks(m, topology), topology,
                                                *detail::tree_order(topology),
                                                detail::load_cases(m, topology), 1e-12, scratch);
    ASSERT_TRUE(solved_cuts) << file;
    EXPECT_EQ(*solved_cuts, cut_unknowns) << file;
  }
  const Model gough_stewart =
      load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/gough-stewart-6ups.yaml");
  const detail::Topology topology = detail::build_topology(gough_stewart);
  const auto order = detail::tree_order(topology);
  ASSERT_TRUE(order);
  const detail::Blocks blocks = detail::make_blocks(gough_stewart, topology);
  const detail::EndWrenches external = detail::load_cases(gough_stewart, topology);
  detail::TreeScratch scratch;
  EXPECT_FALSE(detail::tree_solve(blocks, topology, *order, external, 1e-12, scratch));
  // Allowed more, the cut solve gives its answer: a passive root support (universal), five
  // others cut at their reactions and six ball joints at their free motions.
  const auto solved_cuts =
      detail::tree_solve(blocks, topology, *order, external, 1e-12, scratch, 64);
  ASSERT_TRUE(solved_cuts);
  EXPECT_EQ(*solved_cuts, 2 + 5 * 6 + 6 * 3);
  EXPECT_LT(detail::check_block_by_block(blocks, topology, scratch.x, external, scratch)
                .relative_residual,
            1e-15);
  SolveOptions factorising;
  factorising.solver = factorising_solver();
  const Mat6 factorised = *solve(gough_stewart, factorising).end_effectors[0].compliance;
  const Mat6 compliance =
      scratch.x.block<6, 6>(detail::deflection_column(topology.effector_ends[0]), 1);
  EXPECT_LT((compliance - factorised).cwiseAbs().maxCoeff(),
            1e-13 * factorised.cwiseAbs().maxCoeff());
}

TEST(TreeSolve, BranchedArmWithEveryKindOfTreeElementMatchesTheFactorisedSolve) {
  const Model m = branched_arm();
  const Result automatic = solve(m);
  ASSERT_EQ(automatic.report.solver, stiffmsa::SolverUsed::tree);
  SolveOptions factorising;
  factorising.solver = factorising_solver();
  expect_same_results(automatic, solve(m, factorising), 1e-13);
  // A workspace's later poses take the tree too.
  Workspace workspace(m);
  Model moved = m;
  moved.points[3].position += Vec3(0.02, -0.01, 0.03);
  const Result pose = solve(workspace, moved);
  EXPECT_EQ(pose.report.solver, stiffmsa::SolverUsed::tree);
  expect_same_results(pose, solve(moved, factorising), 1e-13);
}

// A beam on `supports` rigid supports, with a free node in each span.
Model propped_beam(int supports) {
  Model m;
  for (int i = 0; i <= 2 * (supports - 1); ++i) {
    const std::string point = "P" + std::to_string(i);
    m.add_point(point, Vec3(0.25 * i, 0.05 * (i % 3), 0));
    if (i > 0)
      m.add_beam("L" + std::to_string(i), "P" + std::to_string(i - 1), point, kSteel,
                 Section::tube(0.06, 0.004));
    if (i % 2 == 0) m.add_support("S" + std::to_string(i / 2), point, {}, Connection::rigid());
  }
  m.add_load("P1", "L1", stiffmsa::testing::wrench(0, 30, -400, 5, 0, 0));
  m.add_end_effector("mid", "P1", "L1");
  return m;
}

// One scratch through solves of other models, widths and cut counts (a workspace keeps its own
// from pose to pose) gives bit for bit what a fresh one gives; release_large frees only what is
// above 1 MiB.
TEST(TreeSolve, AScratchKeptBetweenSolvesChangesNoDigit) {
  struct Case {
    Model model;
    detail::Topology topology;
    detail::TreeOrder order;
    detail::Blocks blocks;
    detail::EndWrenches external;
  };
  auto make_case = [](Model m) {
    detail::Topology topology = detail::build_topology(m);
    detail::TreeOrder order = *detail::tree_order(topology);
    detail::Blocks blocks = detail::make_blocks(m, topology);
    detail::EndWrenches external = detail::load_cases(m, topology);
    return Case{std::move(m), std::move(topology), std::move(order), std::move(blocks),
                std::move(external)};
  };
  Model one_effector = branched_arm();
  one_effector.end_effectors.pop_back();
  std::vector<Case> cases;
  cases.push_back(
      make_case(load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/tripteron.yaml")));  // cut
  cases.push_back(make_case(branched_arm()));   // no cut, 13 columns
  cases.push_back(make_case(one_effector));     // no cut, 7 columns
  cases.push_back(make_case(propped_beam(3)));  // cut
  detail::TreeScratch kept;
  for (int round = 0; round < 2; ++round)
    for (const Case& c : cases) {
      detail::TreeScratch fresh;
      const auto fresh_cuts =
          detail::tree_solve(c.blocks, c.topology, c.order, c.external, 1e-12, fresh);
      const auto kept_cuts =
          detail::tree_solve(c.blocks, c.topology, c.order, c.external, 1e-12, kept);
      ASSERT_TRUE(fresh_cuts && kept_cuts) << c.model.name;
      EXPECT_EQ(*kept_cuts, *fresh_cuts);
      ASSERT_EQ(kept.x.rows(), fresh.x.rows());
      ASSERT_EQ(kept.x.cols(), fresh.x.cols());
      EXPECT_TRUE((kept.x.array() == fresh.x.array()).all()) << c.model.name << " round " << round;
      const detail::BlockCheck fresh_check =
          detail::check_block_by_block(c.blocks, c.topology, fresh.x, c.external, fresh);
      const detail::BlockCheck kept_check =
          detail::check_block_by_block(c.blocks, c.topology, kept.x, c.external, kept);
      EXPECT_EQ(kept_check.relative_residual, fresh_check.relative_residual);
      EXPECT_EQ(kept_check.nonzeros, fresh_check.nonzeros);
      EXPECT_EQ(kept_check.pattern, fresh_check.pattern);
    }
  kept.x.resize(1 << 17, 1);  // 1 MiB: kept
  kept.first_run.resize((1 << 17) + 1, 1);
  kept.release_large();
  EXPECT_EQ(kept.x.size(), 1 << 17);
  EXPECT_EQ(kept.first_run.size(), 0);
  EXPECT_GT(kept.block_residual.size(), 0);
}

TEST(TreeSolve, CutsLoopsThroughTheGroundAndFreeMotionsThere) {
  SolveOptions factorising;
  factorising.solver = factorising_solver();
  // A prop under the stub closes a loop through the ground; a preloaded passive hinge in the
  // bracket, on that loop, is held by it.
  Model propped = branched_arm();
  propped.add_support("prop", "stub", {}, Connection::rigid());
  propped.add_point("mid_bracket", Vec3(0.075, -0.14, 0.625));
  propped.links[5].to = "mid_bracket";  // the bracket, now hub - mid_bracket
  propped.add_beam("bracket_outer", "mid_bracket", "stub", kSteel, Section::rect(0.03, 0.05));
  propped.loads[2].link = "bracket_outer";
  propped.add_joint("hinge", "mid_bracket", {"bracket", "bracket_outer"},
                    Connection::passive(Kinematics::revolute(Vec3(0, 0, 1))).preloaded(20.0));
  ASSERT_TRUE(detail::tree_order(detail::build_topology(propped)));
  const Result cut = solve(propped);
  EXPECT_EQ(cut.report.solver, stiffmsa::SolverUsed::tree_with_cuts);
  expect_same_results(cut, solve(propped, factorising), 1e-13);

  // A beam on several supports: 6 cut unknowns each beyond the first.
  const Model beam = propped_beam(5);
  const Result on_beam = solve(beam);
  EXPECT_EQ(on_beam.report.solver, stiffmsa::SolverUsed::tree_with_cuts);
  expect_same_results(on_beam, solve(beam, factorising), 1e-13);
  // As many as are cut: the cut system's condition grows with the span count (the redundant
  // reactions of a long cantilever), the check still passes.
  const Model most = propped_beam(1 + detail::kMostCutUnknowns / 6);
  const Result on_most = solve(most);
  EXPECT_EQ(on_most.report.solver, stiffmsa::SolverUsed::tree_with_cuts);
  expect_same_results(on_most, solve(most, factorising), 1e-13);
  // Beyond kMostCutUnknowns, the sparse factorisation is the cheaper.
  EXPECT_NE(solve(propped_beam(2 + detail::kMostCutUnknowns / 6)).report.solver,
            stiffmsa::SolverUsed::tree_with_cuts);
}

TEST(TreeSolve, LeavesOtherLoopsAndMechanismsToTheFactorisingSolve) {
  // A loop through links alone is no tree.
  Model loop = branched_arm();
  loop.add_beam("tie", "tip_a", "stub", kSteel, Section::circle(0.01));
  loop.loads[0].link = "fore_a";
  loop.loads[2].link = "bracket";
  loop.end_effectors[0].link = "fore_a";
  EXPECT_FALSE(detail::tree_order(detail::build_topology(loop)));
  EXPECT_NE(solve(loop).report.solver, stiffmsa::SolverUsed::tree);
  EXPECT_NE(solve(loop).report.solver, stiffmsa::SolverUsed::tree_with_cuts);

  // A passive joint on one support is a free motion: its cut system is singular, and the
  // factorising solve finds and names it.
  Model passive = branched_arm();
  passive.joints[1].connection = Connection::passive(Kinematics::revolute(Vec3(0, 1, 0.2)));
  passive.loads.clear();
  passive.supports[0].connection.preload.reset();
  ASSERT_TRUE(detail::tree_order(detail::build_topology(passive)));
  const Result mechanism = solve(passive);
  EXPECT_NE(mechanism.report.solver, stiffmsa::SolverUsed::tree);
  EXPECT_NE(mechanism.report.solver, stiffmsa::SolverUsed::tree_with_cuts);
  EXPECT_FALSE(mechanism.end_effectors[0].compliance);
  EXPECT_FALSE(mechanism.report.notes.empty());

  // The tripteron with rigid legs holds the platform's rotations rigidly twice over: its
  // internal moments are undetermined, which the factorising solve reports.
  Model rigid_legs = load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/tripteron.yaml");
  for (Link& link : rigid_legs.links) link.kind = LinkKind(RigidLink{});
  const Result overconstrained = solve(rigid_legs);
  EXPECT_NE(overconstrained.report.solver, stiffmsa::SolverUsed::tree_with_cuts);
  SolveOptions factorising;
  factorising.solver = factorising_solver();
  const Result factorised = solve(rigid_legs, factorising);
  EXPECT_EQ(overconstrained.report.notes, factorised.report.notes);
}

// Running sums are carried in two parts on trees at least kCompensatedFromDepth links deep, in
// one part on shallower ones (a robot's few links), and both agree where both are exact enough.
TEST(TreeSolve, RunningSumsInTwoPartsOnlyOnDeepTrees) {
  Model chain = stiffmsa::testing::beam_chain(
      40, [](int i) { return Vec3(0.05 * i, 0.01 * (i % 2), 0); }, kSteel,
      Section::tube(0.06, 0.004));
  chain.add_load("P40", std::nullopt, stiffmsa::testing::wrench(10, -200, 50, 3, 0, -1));
  const Model robot =
      load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/industrial-6axis.yaml");
  struct Case {
    const Model& model;
    int depth;
  };
  for (const Case& c : {Case{robot, 7}, Case{chain, 40}}) {
    const detail::Topology topology = detail::build_topology(c.model);
    const detail::TreeOrder order = *detail::tree_order(topology);
    EXPECT_EQ(order.depth, c.depth) << c.model.name;
    const detail::Blocks blocks = detail::make_blocks(c.model, topology);
    const detail::EndWrenches external = detail::load_cases(c.model, topology);
    auto solved = [&](int compensated_from_depth) {
      detail::TreeScratch scratch;
      EXPECT_TRUE(detail::tree_solve(blocks, topology, order, external, 1e-12, scratch,
                                     detail::kMostCutUnknowns, compensated_from_depth));
      return scratch.x;
    };
    const detail::RowMajorMatX by_default = solved(detail::kCompensatedFromDepth);
    const detail::RowMajorMatX two_parts = solved(0);
    const detail::RowMajorMatX one_part = solved(std::numeric_limits<int>::max());
    const bool deep = c.depth >= detail::kCompensatedFromDepth;
    EXPECT_TRUE((by_default.array() == (deep ? two_parts : one_part).array()).all())
        << c.model.name;
    // Deflections and wrenches apart, each against its own largest value in the load case.
    for (detail::Index column = 0; column < by_default.cols(); ++column)
      for (const detail::Index part : {detail::Index{0}, detail::Index{6}}) {
        double largest = 0, difference = 0;
        for (detail::Index row = part; row < two_parts.rows(); row += 12)
          for (detail::Index i = row; i < row + 6; ++i) {
            largest = std::max(largest, std::abs(two_parts(i, column)));
            difference = std::max(difference, std::abs(one_part(i, column) - two_parts(i, column)));
          }
        EXPECT_LT(difference, 1e-14 * largest) << c.model.name << ", load case " << column
                                               << (part == 0 ? ", deflections" : ", wrenches");
      }
  }
}

TEST(TreeSolve, TheOrderVisitsEveryGroupAfterTheOneTowardTheSupport) {
  const Model m = branched_arm();
  const detail::Topology topology = detail::build_topology(m);
  const auto order = detail::tree_order(topology);
  ASSERT_TRUE(order);
  ASSERT_EQ(order->groups.size(), topology.groups.size());
  EXPECT_EQ(topology.groups[static_cast<std::size_t>(order->root)].kind,
            detail::ConnectionGroup::Kind::support);
  std::vector<int> position(topology.groups.size(), -1);
  for (std::size_t k = 0; k < order->groups.size(); ++k)
    position[static_cast<std::size_t>(order->groups[k])] = static_cast<int>(k);
  for (std::size_t k = 1; k < order->groups.size(); ++k) {
    const int toward_root = order->toward_root[k];
    EXPECT_EQ(topology.group_of_end[static_cast<std::size_t>(toward_root)], order->groups[k]);
    // The link's other end is in a group visited before.
    EXPECT_LT(position[static_cast<std::size_t>(
                  topology.group_of_end[static_cast<std::size_t>(toward_root ^ 1)])],
              static_cast<int>(k));
  }
}

TEST(TreeSolve, AResidualThatFailsTheCheckIsRedoneByFactorising) {
  const Model m = load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/industrial-6axis.yaml");
  SolveOptions strict;
  strict.max_relative_residual = 1e-300;  // no floating-point solve meets this
  const Result failed = solve(m, strict);
  EXPECT_NE(failed.report.solver, stiffmsa::SolverUsed::tree);
  ASSERT_EQ(failed.report.failed_checks.size(), 1u);
  EXPECT_NE(failed.report.failed_checks[0].find("the relative residual"), std::string::npos);
}

TEST(TreeSolve, ChoosingAFactorisingSolverSkipsTheTree) {
  const Model m = load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/industrial-6axis.yaml");
  SolveOptions options;
  options.solver = SolverKind::sparse_lu;
  EXPECT_EQ(solve(m, options).report.solver, stiffmsa::SolverUsed::sparse_lu);
}

// The cut solve skips the condition estimate where a cheaper bound below it clears the
// threshold (tree_solve): the bound must lie below the true reciprocal condition, 1/(‖A‖₁·‖A⁻¹‖₁)
// from the inverse, hence below the estimate, on matrices well and badly conditioned, and be 0
// where a pivot is zero.
TEST(TreeSolve, TheConditionBoundLiesBelowTheReciprocalCondition) {
  std::srand(19);
  // The reference reciprocal condition comes from an explicit inverse: it carries its rounding.
  constexpr double kReferenceRounding = 1e-12;
  VecX scratch;
  const auto check = [&](const MatX& a, const std::string& what) {
    const Eigen::PartialPivLU<MatX> lu(a);
    const double bound = detail::rcond_lower_bound(a, lu, scratch);
    const double exact = 1 / (a.cwiseAbs().colwise().sum().maxCoeff() *
                              lu.inverse().cwiseAbs().colwise().sum().maxCoeff());
    EXPECT_GT(bound, 0) << what;
    EXPECT_LE(bound, exact * (1 + kReferenceRounding)) << what;
    EXPECT_LE(exact, lu.rcond() * (1 + kReferenceRounding)) << what;
  };
  for (const Eigen::Index n : {1, 2, 5, 16, 21, 32}) {
    const MatX random = MatX::Random(n, n);
    check(random, "random " + std::to_string(n));
    // Nearly singular: the last column a combination of the others but for 1e-9.
    MatX nearly = random;
    if (n > 1)
      nearly.col(n - 1) = nearly.leftCols(n - 1) * VecX::Random(n - 1) + 1e-9 * VecX::Random(n);
    check(nearly, "nearly singular " + std::to_string(n));
    // Rows of very different sizes, as a cut system before it is equilibrated.
    MatX graded = random;
    for (Eigen::Index i = 0; i < n; ++i) graded.row(i) *= std::pow(10.0, 6.0 * i / n);
    check(graded, "graded " + std::to_string(n));
  }
  MatX singular = MatX::Random(6, 6);
  singular.col(3).setZero();
  EXPECT_EQ(detail::rcond_lower_bound(singular, Eigen::PartialPivLU<MatX>(singular), scratch), 0);
  MatX not_finite = MatX::Random(6, 6);
  not_finite(4, 2) = std::nan("");
  EXPECT_EQ(detail::rcond_lower_bound(not_finite, Eigen::PartialPivLU<MatX>(not_finite), scratch),
            0);
}

// The check is compiled for 7 load cases (one end effector) and for any count: both are
// asked, with the arm's two end effectors (13 load cases) and with one.
class BlockCheck : public ::testing::TestWithParam<int> {
 protected:
  Model arm() const {
    Model m = branched_arm();
    m.end_effectors.resize(static_cast<std::size_t>(GetParam()));
    return m;
  }
};

TEST_P(BlockCheck, SeesAWrongOrNonFiniteSolution) {
  const Model m = arm();
  const detail::Topology topology = detail::build_topology(m);
  const auto order = detail::tree_order(topology);
  ASSERT_TRUE(order);
  const detail::Blocks blocks = detail::make_blocks(m, topology);
  const detail::EndWrenches external = detail::load_cases(m, topology);
  ASSERT_EQ(external.columns(), 1 + 6 * GetParam());
  detail::TreeScratch scratch;
  const auto cut_unknowns = detail::tree_solve(blocks, topology, *order, external, 1e-12, scratch);
  ASSERT_TRUE(cut_unknowns);
  ASSERT_EQ(*cut_unknowns, 0);
  detail::RowMajorMatX x = scratch.x;
  const detail::BlockCheck right =
      detail::check_block_by_block(blocks, topology, x, external, scratch);
  EXPECT_LT(right.relative_residual, 1e-15);
  // One deflection off by a hundredth of the largest unknown: above the default limit of the
  // relative residual, so the solve would be redone by factorising. (The ratio is normwise:
  // ‖A‖∞ here is the support's 8e6 N/m, so smaller errors hide below it, as in any solve.)
  const double largest = x.cwiseAbs().maxCoeff();
  const detail::Index row = detail::deflection_column(5) + 2;
  x(row, detail::kLoadCase) += 0.01 * largest;
  EXPECT_GT(detail::check_block_by_block(blocks, topology, x, external, scratch).relative_residual,
            SolveOptions{}.max_relative_residual);
  // A value that is not finite fails it, in any column, whether or not a coefficient is zero.
  const double inf = std::numeric_limits<double>::infinity();
  for (const double bad : {std::nan(""), inf, -inf}) {
    detail::RowMajorMatX wrong = x;
    wrong(row, external.columns() - 1) = bad;
    EXPECT_EQ(
        detail::check_block_by_block(blocks, topology, wrong, external, scratch).relative_residual,
        INFINITY)
        << bad;
  }
  // So does a coefficient or a right-hand side that is not finite.
  Model nan_spring = m;
  nan_spring.joints[1].connection.stiffness = MatX::Constant(1, 1, std::nan(""));
  EXPECT_EQ(detail::check_block_by_block(detail::make_blocks(nan_spring, topology), topology, x,
                                         external, scratch)
                .relative_residual,
            INFINITY);
  Model nan_preload = m;
  nan_preload.joints[1].connection.preload = VecX::Constant(1, std::nan(""));
  EXPECT_EQ(detail::check_block_by_block(detail::make_blocks(nan_preload, topology), topology, x,
                                         external, scratch)
                .relative_residual,
            INFINITY);
  Model inf_load = m;
  inf_load.loads[2].wrench(2) = -INFINITY;
  EXPECT_EQ(detail::check_block_by_block(blocks, topology, x,
                                         detail::load_cases(inf_load, topology), scratch)
                .relative_residual,
            INFINITY);
  // The fingerprint follows the positions written, not the numbers.
  EXPECT_EQ(right.pattern, detail::pattern_fingerprint(blocks));
  Model moved = m;
  moved.points[2].position.x() += 0.1;
  EXPECT_EQ(detail::pattern_fingerprint(detail::make_blocks(moved, topology)), right.pattern);
  Model rigid_elbow = m;
  rigid_elbow.joints[1].connection = Connection::rigid();
  EXPECT_NE(detail::pattern_fingerprint(detail::make_blocks(rigid_elbow, topology)), right.pattern);
}

INSTANTIATE_TEST_SUITE_P(EndEffectors, BlockCheck, ::testing::Values(1, 2), [](const auto& info) {
  return std::to_string(info.param) + "_end_effectors";
});
