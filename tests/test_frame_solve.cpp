// The frame solve (solver/frame_solver.hpp): frames whose links are all flexible and whose
// connections all weld are solved by the condensed displacement system; every number they
// report must be the one the factorised mixed system gives, and a condensation that would lose
// digits must be left to the factorising solve.
#include <gtest/gtest.h>

#include <filesystem>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include "assembly/topology.hpp"
#include "builders.hpp"
#include "solve_comparison.hpp"
#include "solver/frame_solver.hpp"
#include "stiffmsa/config.hpp"
#include "stiffmsa/stiffmsa.hpp"

using namespace stiffmsa;
using namespace stiffmsa::testing;

namespace {

using stiffmsa::testing::wrench;

// The building of test_solver.cpp, loaded on its roof and on a floor, in three directions.
Model loaded_building() {
  Model m = building(3, 3, 4);
  m.add_load("n3_3_4", std::string("cn3_3_4"), wrench(1.2e4, -3e3, -2e4, 500, 0, 800));
  m.add_load("n1_2_2", std::string("cn1_2_2"), wrench(0, 8e3, 0, 0, -1.5e3, 0));
  return m;
}

// Beams from P0 (clamped) to P1, side by side: a loop through P1's weld that is no tree.
Model beams_side_by_side(const std::vector<Section>& sections) {
  Model m;
  m.add_point("P0", Vec3::Zero());
  m.add_point("P1", Vec3(0.9, 0.2, -0.1));
  for (std::size_t k = 0; k < sections.size(); ++k)
    m.add_beam("B" + std::to_string(k), "P0", "P1", kFrameSteel, sections[k]);
  m.add_support("clamp", "P0", {}, Connection::rigid());
  m.add_end_effector("tip", "P1", std::string("B0"));
  return m;
}

// A triangle of rods clamped at P0: P0–M–P1 and P0–P1, welded at M and P1 unless told.
Model clamped_triangle() {
  Model m;
  m.add_point("P0", Vec3::Zero());
  m.add_point("M", Vec3(0.5, 0, 0));
  m.add_point("P1", Vec3(1, 0.4, 0));
  m.add_beam("a", "P0", "M", kFrameSteel, Section::circle(0.03));
  m.add_beam("b", "M", "P1", kFrameSteel, Section::circle(0.03));
  m.add_beam("c", "P0", "P1", kFrameSteel, Section::circle(0.03));
  m.add_support("clamp", "P0", {}, Connection::rigid());
  return m;
}

double relative_difference(const Mat6& a, const Mat6& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

}  // namespace

TEST(FrameSolve, ABuildingFrameMatchesTheFactorisedSolveInEveryNumber) {
  const Model m = loaded_building();
  const Result frame = solve(m);
  ASSERT_EQ(frame.report.solver, stiffmsa::SolverUsed::frame);
  // The condensed K's condition, from its own factors: a well-conditioned building.
  EXPECT_GT(frame.report.reciprocal_condition, 1e-6);
  EXPECT_LE(frame.report.reciprocal_condition, 1.0);
  SolveOptions options;
  options.solver = factorising_solver();
  const Result factorised = solve(m, options);
  ASSERT_NE(factorised.report.solver, stiffmsa::SolverUsed::frame);
  expect_same_results(frame, factorised, 1e-11, 1e-14);
  EXPECT_LT(frame.report.equilibrium_error, 1e-12);
}

TEST(FrameSolve, FreeEndsAndLockedActuatorsAreNodesOfTheFrame) {
  // The triangle with a bracket sticking out of P1 to a free end that carries the load, and a
  // locked actuator at M.
  Model m = clamped_triangle();
  m.add_point("E", Vec3(1.2, 0.4, 0.3));
  m.add_beam("bracket", "P1", "E", kFrameSteel, Section::circle(0.02));
  m.add_joint("brake", "M", {"a", "b"}, Connection::actuated(Kinematics::revolute(Vec3::UnitZ())));
  m.add_load("E", std::nullopt, wrench(30, -200, 80, 0, 4, 0));
  m.add_end_effector("tool", "E");
  const Result frame = solve(m);
  ASSERT_EQ(frame.report.solver, stiffmsa::SolverUsed::frame);
  SolveOptions options;
  options.solver = factorising_solver();
  const Result factorised = solve(m, options);
  ASSERT_NE(factorised.report.solver, stiffmsa::SolverUsed::frame);
  // Slender members: K's condition ~1e6 here, and each wrench, K12·Δt, carries its rounding
  // (ε·‖K12‖·|Δt|), which the node rows' residual shows.
  expect_same_results(frame, factorised, 1e-12, 1e-12);
  // The free end carries the load; the brake's effort is its torque about its axis.
  EXPECT_LT((*frame.links[3].to.wrench - wrench(30, -200, 80, 0, 4, 0)).cwiseAbs().maxCoeff(),
            1e-12 * 200);
  ASSERT_TRUE(frame.joints[0].effort);
  EXPECT_GT(std::abs((*frame.joints[0].effort)(0)), 1.0);
}

TEST(FrameSolve, APartHeldByNoSupportIsLeftToTheFactorisingSolve) {
  // A second triangle floating beside the clamped one: K is singular there, the Cholesky fails,
  // and the factorising solve reports the free motion.
  Model m = beams_side_by_side({Section::tube(0.06, 0.004), Section::tube(0.06, 0.004)});
  m.add_point("Q0", Vec3(0, 2, 0));
  m.add_point("Q1", Vec3(1, 2, 0));
  m.add_beam("f0", "Q0", "Q1", kFrameSteel, Section::circle(0.03));
  m.add_beam("f1", "Q0", "Q1", kFrameSteel, Section::circle(0.03));
  const detail::Topology topology = detail::build_topology(m);
  const detail::Blocks blocks = detail::make_blocks(m, topology);
  const auto plan = detail::frame_plan(topology, blocks);
  ASSERT_TRUE(plan);
  detail::RowMajorMatX x;
  // Declined without a word from the library (CHOLMOD would print its warning).
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  EXPECT_FALSE(detail::frame_solve(blocks, topology, *plan, detail::load_cases(m, topology), x));
  EXPECT_EQ(::testing::internal::GetCapturedStdout(), "");
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  EXPECT_THROW(solve(m), SingularModelError);
}

TEST(FrameSolve, BeamsSideBySideAddTheirStiffnesses) {
  // One beam's compliance at P1 comes from the tree solve (test_closed_forms.cpp pins it to the
  // cantilever's closed form); beams side by side between the same welds add their stiffnesses.
  const Section tube = Section::tube(0.06, 0.004), bar = Section::rect(0.03, 0.05);
  const Mat6 tube_alone = *solve(beams_side_by_side({tube})).end_effectors[0].compliance;
  const Mat6 bar_alone = *solve(beams_side_by_side({bar})).end_effectors[0].compliance;
  const Result two_tubes = solve(beams_side_by_side({tube, tube}));
  ASSERT_EQ(two_tubes.report.solver, stiffmsa::SolverUsed::frame);
  EXPECT_LT(relative_difference(*two_tubes.end_effectors[0].compliance, 0.5 * tube_alone), 1e-12);
  const Result tube_and_bar = solve(beams_side_by_side({tube, bar}));
  ASSERT_EQ(tube_and_bar.report.solver, stiffmsa::SolverUsed::frame);
  const Mat6 combined = (Mat6(tube_alone.inverse()) + Mat6(bar_alone.inverse())).inverse();
  EXPECT_LT(relative_difference(*tube_and_bar.end_effectors[0].compliance, combined), 1e-11);
  // Each beam carries its share of a load: the wrenches at P1 sum to it.
  Model loaded = beams_side_by_side({tube, bar});
  const Vec6 load = wrench(50, -400, 120, 3, 0, -7);
  loaded.add_load("P1", std::string("B1"), load);
  const Result r = solve(loaded);
  ASSERT_EQ(r.report.solver, stiffmsa::SolverUsed::frame);
  const Vec6 carried = *r.links[0].to.wrench + *r.links[1].to.wrench;
  EXPECT_LT((carried - load).cwiseAbs().maxCoeff(), 1e-12 * load.cwiseAbs().maxCoeff());
  // The clamp at the origin holds the load and its moment about the origin.
  const Vec3 at = loaded.points[1].position;
  Vec6 held;
  held << -load.head<3>(), -(load.tail<3>() + at.cross(load.head<3>()));
  EXPECT_LT((*r.supports[0].reaction - held).cwiseAbs().maxCoeff(),
            1e-11 * held.cwiseAbs().maxCoeff());
}

TEST(FrameSolve, PlanCoversOnlyFramesOfFlexibleLinksAndWelds) {
  const Model m = building(2, 1, 2);
  const detail::Topology topology = detail::build_topology(m);
  const detail::Blocks blocks = detail::make_blocks(m, topology);
  const auto plan = detail::frame_plan(topology, blocks);
  ASSERT_TRUE(plan);
  // A node per point above the ground (3 × 2 × 2), the ground's ends held by their supports.
  EXPECT_EQ(plan->nodes, 12);
  for (int end = 0; end < topology.end_count(); ++end) {
    const int point = topology.end_points[static_cast<std::size_t>(end)];
    const bool on_the_ground = m.points[static_cast<std::size_t>(point)].position.z() == 0;
    EXPECT_EQ(plan->node_of_end[static_cast<std::size_t>(end)] < 0, on_the_ground) << "end " << end;
  }
  auto is_frame = [](const Model& model) {
    const detail::Topology t = detail::build_topology(model);
    return detail::frame_plan(t, detail::make_blocks(model, t)).has_value();
  };
  Model rigid_link = m;
  rigid_link.links.back().kind = RigidLink{};
  EXPECT_FALSE(is_frame(rigid_link));
  Model hinged = m;  // every end at a roof corner pinned about y
  hinged.add_joint("hinge", "n0_0_2", {"cn0_0_2", "xn0_0_2", "yn0_0_2"},
                   Connection::passive(Kinematics::revolute(Vec3::UnitY())));
  EXPECT_FALSE(is_frame(hinged));
  Model elastic_support = m;
  elastic_support.supports.front().connection =
      Connection::elastic(Kinematics::spherical(), MatX(1e8 * Eigen::Matrix3d::Identity()));
  EXPECT_FALSE(is_frame(elastic_support));
  // The triangle: welded at M, a frame; spliced there by a spring, none.
  EXPECT_TRUE(is_frame(clamped_triangle()));
  Model spliced = clamped_triangle();
  spliced.add_joint("splice", "M", {"a", "b"},
                    Connection::elastic(Kinematics::revolute(Vec3::UnitZ()), 1e5));
  EXPECT_FALSE(is_frame(spliced));
  Model locked = m;  // a locked actuator is held rigidly: still a weld
  locked.add_joint("brake", "n0_0_2", {"cn0_0_2", "xn0_0_2", "yn0_0_2"},
                   Connection::actuated(Kinematics::revolute(Vec3::UnitY())));
  EXPECT_TRUE(is_frame(locked));
}

// A hairpin: two chains of `beams` slender rods (20 mm over 1.5 m) from one clamp, joined at
// their tips by a bar and loaded there. Its loop closes through the tip, not the ground: no
// tree. K's condition grows with the rods' slenderness and with the beams per chain.
Model hairpin(int beams) {
  const double length = 1.5;
  Model m;
  m.add_point("A0", Vec3::Zero());
  for (int i = 1; i <= beams; ++i) {
    const std::string a = "A" + std::to_string(i), b = "B" + std::to_string(i);
    m.add_point(a, Vec3(length * i / beams, 0, 0));
    m.add_point(b, Vec3(length * i / beams, 0.3, 0));
    m.add_beam("a" + std::to_string(i), "A" + std::to_string(i - 1), a, kFrameSteel,
               Section::circle(0.02));
    m.add_beam("b" + std::to_string(i), i == 1 ? std::string("A0") : "B" + std::to_string(i - 1), b,
               kFrameSteel, Section::circle(0.02));
  }
  const std::string tip = "A" + std::to_string(beams);
  m.add_beam("tip_bar", tip, "B" + std::to_string(beams), kFrameSteel, Section::circle(0.02));
  m.add_support("clamp", "A0", {}, Connection::rigid());
  m.add_load(tip, "a" + std::to_string(beams), wrench(30, -200, 80, 0, 4, 0));
  m.add_end_effector("tip", tip, "a" + std::to_string(beams));
  return m;
}

TEST(FrameSolve, ThePlanHoldsKsPatternAndWhereEachLinksPartsGo) {
  // K's pattern from the plan against one made here from the links: a 6×6 block for every pair
  // of nodes a link joins (each node with itself), rows sorted in each column.
  const Model m = building(2, 1, 2);
  const detail::Topology topology = detail::build_topology(m);
  const auto plan = detail::frame_plan(topology, detail::make_blocks(m, topology));
  ASSERT_TRUE(plan);
  const int n = 6 * plan->nodes;
  auto node_of = [&](int l, int a) {
    return plan->node_of_end[static_cast<std::size_t>(2 * l + a)];
  };
  std::vector<std::set<int>> joined(static_cast<std::size_t>(plan->nodes));
  for (int l = 0; l < topology.link_count; ++l)
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        if (node_of(l, a) >= 0 && node_of(l, b) >= 0)
          joined[static_cast<std::size_t>(node_of(l, b))].insert(node_of(l, a));
  ASSERT_EQ(plan->column_starts.size(), static_cast<std::size_t>(n) + 1);
  EXPECT_EQ(plan->column_starts.front(), 0);
  EXPECT_EQ(static_cast<std::size_t>(plan->column_starts.back()), plan->rows.size());
  for (int column = 0; column < n; ++column) {
    std::vector<int> expected;
    for (int node : joined[static_cast<std::size_t>(column / 6)])
      for (int i = 0; i < 6; ++i) expected.push_back(6 * node + i);
    const std::vector<int> rows(
        plan->rows.begin() + plan->column_starts[static_cast<std::size_t>(column)],
        plan->rows.begin() + plan->column_starts[static_cast<std::size_t>(column) + 1]);
    EXPECT_EQ(rows, expected) << "column " << column;
  }
  ASSERT_EQ(plan->parts.size(), 4 * static_cast<std::size_t>(topology.link_count));
  for (int l = 0; l < topology.link_count; ++l)
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        const detail::FramePlan::Part& part =
            plan->parts[static_cast<std::size_t>(4 * l + 2 * a + b)];
        const int row_node = node_of(l, a), column_node = node_of(l, b);
        EXPECT_EQ(part.first < 0, row_node < 0 || column_node < 0);
        if (part.first < 0) continue;
        for (int j = 0; j < 6; ++j)
          for (int i = 0; i < 6; ++i) {
            const int at = part.first + j * part.stride + i;
            const auto column = static_cast<std::size_t>(6 * column_node + j);
            EXPECT_GE(at, plan->column_starts[column]);
            EXPECT_LT(at, plan->column_starts[column + 1]);
            EXPECT_EQ(plan->rows[static_cast<std::size_t>(at)], 6 * row_node + i);
          }
      }
}

TEST(FrameSolve, NearItsBarAFrameKeepsTenDigits) {
  // Three rods per chain: K's reciprocal condition ~2e-6, just above the bar (docs/theory.md
  // §7.3 tabulates the hairpins).
  const Model m = hairpin(3);
  const Result frame = solve(m);
  ASSERT_EQ(frame.report.solver, stiffmsa::SolverUsed::frame);
  EXPECT_LT(frame.report.reciprocal_condition, 10 * detail::kFrameLeastRcond);
  SolveOptions options;
  options.solver = factorising_solver();
  const Result factorised = solve(m, options);
  ASSERT_NE(factorised.report.solver, stiffmsa::SolverUsed::frame);
  expect_same_results(frame, factorised, 1e-10, 1e-10);
}

TEST(FrameSolve, DeclinesACondensationThatWouldLoseDigits) {
  // 150 rods per chain: K's reciprocal condition ~2e-8, below the bar, so the factorised mixed
  // system answers, as accurately as ever.
  const Model m = hairpin(150);
  const detail::Topology topology = detail::build_topology(m);
  ASSERT_FALSE(detail::tree_order(topology));
  const detail::Blocks blocks = detail::make_blocks(m, topology);
  const auto plan = detail::frame_plan(topology, blocks);
  ASSERT_TRUE(plan);
  const detail::EndWrenches external = detail::load_cases(m, topology);
  detail::RowMajorMatX x;
  EXPECT_FALSE(detail::frame_solve(blocks, topology, *plan, external, x));
  // With the bar lowered to nothing the condensation answers, its condition estimate below it.
  const auto forced = detail::frame_solve(blocks, topology, *plan, external, x, 0.0);
  ASSERT_TRUE(forced);
  EXPECT_LT(forced->reciprocal_condition, detail::kFrameLeastRcond);
  EXPECT_GT(forced->reciprocal_condition, 0.0);
  const Result r = solve(m);
  EXPECT_TRUE(r.report.solver == stiffmsa::SolverUsed::klu ||
              r.report.solver == stiffmsa::SolverUsed::sparse_lu)
      << to_string(r.report.solver);
  EXPECT_LT(r.report.relative_residual, 1e-15);
  // Any K below the bar is declined, however well-conditioned: the building's is ~2e-5.
  const Model frame = building(2, 1, 2);
  const detail::Topology frame_topology = detail::build_topology(frame);
  const detail::Blocks frame_blocks = detail::make_blocks(frame, frame_topology);
  const auto frame_plan = detail::frame_plan(frame_topology, frame_blocks);
  ASSERT_TRUE(frame_plan);
  EXPECT_FALSE(detail::frame_solve(frame_blocks, frame_topology, *frame_plan,
                                   detail::load_cases(frame, frame_topology), x, 1.0));
}

TEST(FrameSolve, PosesOfAWorkspaceMatchOneShotSolves) {
  const Model m = loaded_building();
  Workspace workspace(m);
  Model moved = m;
  for (auto& point : moved.points) point.position.x() *= 1.05;  // a longer building, same topology
  moved.loads.front().wrench *= -2;
  for (const Model* pose : std::initializer_list<const Model*>{&m, &moved, &m}) {
    const Result kept = solve(workspace, *pose);
    ASSERT_EQ(kept.report.solver, stiffmsa::SolverUsed::frame);
    const Result fresh = solve(*pose);
    expect_same_results(kept, fresh, 1e-15, 1e-14);
  }
  // A pose whose link became rigid is not this workspace's frame.
  Model stiffened = m;
  stiffened.links.front().kind = RigidLink{};
  EXPECT_THROW(solve(workspace, stiffened), InputError);
}

// CHOLMOD fills each large supernode of its factor in an OpenMP team of 4 threads, whatever the
// cores: the frame solve runs that work on the calling thread, so that a frame on 2 cores, or a
// sweep whose workers each solve one, does not have more threads than cores waiting on each
// other. The runtime would keep its team's threads alive after the solve: none may appear.
TEST(FrameSolve, FactorisesOnTheCallingThreadAlone) {
  if (!STIFFMSA_HAVE_OPENMP_RUNTIME) GTEST_SKIP() << "built without libgomp's API (CMakeLists.txt)";
  if (!std::filesystem::is_directory("/proc/self/task"))
    GTEST_SKIP() << "threads are counted in /proc/self/task";
  const auto threads = [] {
    const std::filesystem::directory_iterator tasks("/proc/self/task");
    return std::distance(begin(tasks), end(tasks));
  };
  const Model m =
      building(5, 5, 10);  // 960 beams: supernodes above CHOLMOD's 1 024-entry threshold
  const auto before = threads();
  const Result result = solve(m);
  ASSERT_EQ(result.report.solver, stiffmsa::SolverUsed::frame);
  EXPECT_LE(threads(), before);  // a thread of the test runner's may end meanwhile; none may start
}
