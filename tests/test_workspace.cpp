// A workspace built once serves every model of the same topology: numbers are refilled and the
// factorisation redone, with the same results as a fresh solve.
#include <gtest/gtest.h>

#include "builders.hpp"
#include "closed_forms.hpp"
#include "stiffmsa/stiffmsa.hpp"

using namespace stiffmsa;

namespace {

Model arm(double elbow_x, double joint_stiffness) {
  Model m;
  const Material steel{2.1e11, 0.3, std::nullopt};
  m.add_point("O", Vec3::Zero());
  m.add_point("A", Vec3(0, 0, 0.4));
  m.add_point("B", Vec3(elbow_x, 0.1, 0.5));
  m.add_point("E", Vec3(elbow_x + 0.3, 0.0, 0.3));
  m.add_beam("column", "O", "A", steel, Section::tube(0.1, 0.006));
  m.add_beam("upper", "A", "B", steel, Section::tube(0.08, 0.005));
  m.add_rigid_link("fore", "B", "E");
  m.add_support("base", "O", {}, Connection::rigid());
  m.add_joint("shoulder", "A", {"column", "upper"},
              Connection::elastic(Kinematics::revolute(Vec3::UnitY()), joint_stiffness));
  m.add_joint("elbow", "B", {"upper", "fore"},
              Connection::elastic(Kinematics::revolute(Vec3::UnitY()), 0.5 * joint_stiffness));
  m.add_load("E", std::nullopt, stiffmsa::testing::wrench(0, 0, -200, 0, 0, 0));
  m.add_end_effector("tool", "E");
  return m;
}

}  // namespace

// The arm is a tree: `auto` solves it without factorising; sparse_lu refills the recorded
// pattern and refactorises. Both must follow the pose.
class WorkspaceWithEverySolve : public ::testing::TestWithParam<SolverKind> {};

TEST_P(WorkspaceWithEverySolve, RefilledPosesMatchFreshSolves) {
  SolveOptions options;
  options.solver = GetParam();
  Workspace workspace(arm(0.5, 2e5));
  for (double x : {0.5, 0.62, 0.8}) {
    for (double k : {2e5, 7e5}) {
      const Model pose = arm(x, k);
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
  const Result near = solve(workspace, arm(0.5, 2e5), options),
               far = solve(workspace, arm(0.8, 2e5), options);
  EXPECT_GT(reference::relative_difference(*far.end_effectors[0].compliance,
                                           *near.end_effectors[0].compliance),
            0.05);
}

// Same names and connectivity, but the elbow is now rigid: its block writes other positions,
// which the refill (factorising) or the pattern's fingerprint (tree) catches.
TEST_P(WorkspaceWithEverySolve, ABlockThatWritesOtherPositionsIsRejected) {
  SolveOptions options;
  options.solver = GetParam();
  Workspace workspace(arm(0.5, 2e5));
  Model other = arm(0.5, 2e5);
  other.joints.back().connection = Connection::rigid();
  EXPECT_THROW(solve(workspace, other, options), InputError);
  const Result again =
      solve(workspace, arm(0.62, 2e5), options);  // the workspace still serves its topology
  EXPECT_LT(
      reference::relative_difference_scaled(*again.end_effectors[0].compliance,
                                            *solve(arm(0.62, 2e5)).end_effectors[0].compliance),
      1e-13);
}

INSTANTIATE_TEST_SUITE_P(Solves, WorkspaceWithEverySolve,
                         ::testing::Values(SolverKind::automatic, SolverKind::sparse_lu));

// A tree workspace records its pattern only when a factorising solve needs it, and then from
// the model it was built from: a first factorised model of another pattern (here a passive
// elbow: free motion, not a tree solve) is refused without spoiling later solves.
TEST(Workspace, ThePatternIsTheReferencesWhateverIsFactorisedFirst) {
  Workspace workspace(arm(0.5, 2e5));
  Model passive = arm(0.5, 2e5);
  passive.joints.back().connection.stiffness.reset();
  passive.loads.clear();
  EXPECT_THROW(solve(workspace, passive), InputError);
  SolveOptions klu;
  klu.solver = SolverKind::sparse_lu;
  const Result again = solve(workspace, arm(0.62, 2e5), klu);
  EXPECT_EQ(again.report.solver, stiffmsa::SolverUsed::sparse_lu);
  EXPECT_LT(
      reference::relative_difference_scaled(*again.end_effectors[0].compliance,
                                            *solve(arm(0.62, 2e5)).end_effectors[0].compliance),
      1e-13);
  EXPECT_EQ(workspace.size().unknowns, 3 * 24);
}

TEST(Workspace, ADifferentTopologyIsRejected) {
  Workspace workspace(arm(0.5, 2e5));
  Model other = arm(0.5, 2e5);
  other.joints.pop_back();  // the elbow's ends are now welded: another topology
  EXPECT_THROW(solve(workspace, other), InputError);
  EXPECT_EQ(workspace.size().unknowns, 3 * 24);
}

TEST(Workspace, CheckReportsTheSquareSystemWithoutSolving) {
  const SystemSize size = check(arm(0.5, 2e5));
  EXPECT_EQ(size.unknowns, 72);
  EXPECT_EQ(size.equations, 72);
  EXPECT_GT(size.nonzeros, 72);
}
