// A workspace built once serves every model of the same topology: numbers are refilled and the
// factorisation redone, with the same results as a fresh solve.
#include <gtest/gtest.h>

#include "builders.hpp"
#include "closed_forms.hpp"
#include "stiffmsa/stiffmsa.hpp"

using namespace stiffmsa;

namespace {}  // namespace

// The arm is a tree: `auto` solves it without factorising; sparse_lu refills the recorded
// pattern and refactorises. Both must follow the pose.
class WorkspaceWithEverySolve : public ::testing::TestWithParam<SolverKind> {};

TEST_P(WorkspaceWithEverySolve, RefilledPosesMatchFreshSolves) {
  SolveOptions options;
  options.solver = GetParam();
  Workspace workspace(stiffmsa::testing::two_joint_arm(0.5, 2e5));
  for (double x : {0.5, 0.62, 0.8}) {
    for (double k : {2e5, 7e5}) {
      const Model pose = stiffmsa::testing::two_joint_arm(x, k);
      const Result reused = solve(workspace, pose, options);
      const Result fresh = solve(pose, options);
      EXPECT_EQ(reused.report.solver, GetParam() == SolverKind::automatic
                                          ? stiffmsa::SolverUsed::tree
                                          : stiffmsa::SolverUsed::sparse_lu);
      EXPECT_LT(reference::relative_difference_scaled(*reused.end_effectors[0].compliance,
                                                      *fresh.end_effectors[0].compliance),
                1e-13);
      EXPECT_LT(reference::relative_difference(*reused.end_effectors[0].deflection,
                                               *fresh.end_effectors[0].deflection),
                1e-13);
    }
  }
  // A changed pose changes the answer: the workspace holds no stale numbers.
  const Result near = solve(workspace, stiffmsa::testing::two_joint_arm(0.5, 2e5), options),
               far = solve(workspace, stiffmsa::testing::two_joint_arm(0.8, 2e5), options);
  EXPECT_GT(reference::relative_difference(*far.end_effectors[0].compliance,
                                           *near.end_effectors[0].compliance),
            0.05);
}

// Same names and connectivity, but the elbow is now rigid: its block writes other positions,
// which the refill (factorising) or the pattern's fingerprint (tree) catches.
TEST_P(WorkspaceWithEverySolve, ABlockThatWritesOtherPositionsIsRejected) {
  SolveOptions options;
  options.solver = GetParam();
  Workspace workspace(stiffmsa::testing::two_joint_arm(0.5, 2e5));
  Model other = stiffmsa::testing::two_joint_arm(0.5, 2e5);
  other.joints.back().connection = Connection::rigid();
  EXPECT_THROW(solve(workspace, other, options), InputError);
  const Result again = solve(workspace, stiffmsa::testing::two_joint_arm(0.62, 2e5),
                             options);  // the workspace still serves its topology
  EXPECT_LT(reference::relative_difference_scaled(
                *again.end_effectors[0].compliance,
                *solve(stiffmsa::testing::two_joint_arm(0.62, 2e5)).end_effectors[0].compliance),
            1e-13);
}

INSTANTIATE_TEST_SUITE_P(Solves, WorkspaceWithEverySolve,
                         ::testing::Values(SolverKind::automatic, SolverKind::sparse_lu));

// A tree workspace records its pattern only when a factorising solve needs it, and then from
// the model it was built from: a first factorised model of another pattern (here a passive
// elbow: free motion, not a tree solve) is refused without spoiling later solves.
TEST(Workspace, ThePatternIsTheReferencesWhateverIsFactorisedFirst) {
  Workspace workspace(stiffmsa::testing::two_joint_arm(0.5, 2e5));
  Model passive = stiffmsa::testing::two_joint_arm(0.5, 2e5);
  passive.joints.back().connection.stiffness.reset();
  passive.loads.clear();
  EXPECT_THROW(solve(workspace, passive), InputError);
  SolveOptions klu;
  klu.solver = SolverKind::sparse_lu;
  const Result again = solve(workspace, stiffmsa::testing::two_joint_arm(0.62, 2e5), klu);
  EXPECT_EQ(again.report.solver, stiffmsa::SolverUsed::sparse_lu);
  EXPECT_LT(reference::relative_difference_scaled(
                *again.end_effectors[0].compliance,
                *solve(stiffmsa::testing::two_joint_arm(0.62, 2e5)).end_effectors[0].compliance),
            1e-13);
  EXPECT_EQ(workspace.size().unknowns, 3 * 24);
}

TEST(Workspace, ADifferentTopologyIsRejected) {
  Workspace workspace(stiffmsa::testing::two_joint_arm(0.5, 2e5));
  Model other = stiffmsa::testing::two_joint_arm(0.5, 2e5);
  other.joints.pop_back();  // the elbow's ends are now welded: another topology
  EXPECT_THROW(solve(workspace, other), InputError);
  EXPECT_EQ(workspace.size().unknowns, 3 * 24);
}

TEST(Workspace, CheckReportsTheSquareSystemWithoutSolving) {
  const SystemSize size = check(stiffmsa::testing::two_joint_arm(0.5, 2e5));
  EXPECT_EQ(size.unknowns, 72);
  EXPECT_EQ(size.equations, 72);
  EXPECT_GT(size.nonzeros, 72);
}
