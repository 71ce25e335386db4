// A model compiled into its structure and its values: slots named by their keys, a pose solved
// from values alone with the numbers of a fresh solve, and per-pose checks of values only.
#include <gtest/gtest.h>

#include <algorithm>

#include "builders.hpp"
#include "stiffmsa/stiffmsa.hpp"

using namespace stiffmsa;

namespace {

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST(Structure, SlotsAreNamedByTheirKeys) {
  const Structure structure(stiffmsa::testing::two_joint_arm(0.3, 1e5));
  const auto& names = structure.slot_names();
  ASSERT_EQ(names.size(), structure.value_count());
  EXPECT_EQ(names.front(), "points.O[0]");
  const auto E = structure.find_slot("links.upper.material.E");
  ASSERT_TRUE(E);
  EXPECT_EQ(structure.default_values()[*E], 2.1e11);
  const auto k = structure.find_slot("joints.elbow.stiffness[0][0]");
  ASSERT_TRUE(k);
  EXPECT_EQ(structure.default_values()[*k], 0.5e5);
  const auto Fz = structure.find_slot("loads[0].wrench[2]");
  ASSERT_TRUE(Fz);
  EXPECT_EQ(structure.default_values()[*Fz], -200.0);
  EXPECT_FALSE(structure.find_slot("links.lower.material.E"));
  EXPECT_EQ(structure.values_of(structure.model()), structure.default_values());
}

// Every pose of the arm from values alone equals the fresh solve of its model, bit for bit, with
// one workspace from pose to pose.
TEST(Structure, PosesFromValuesEqualFreshSolves) {
  const Structure structure(stiffmsa::testing::two_joint_arm(0.3, 1e5));
  for (SolverKind solver : {SolverKind::automatic, SolverKind::sparse_lu}) {
    SolveOptions options;
    options.solver = solver;
    Workspace workspace(structure);
    for (const auto& [x, k] : {std::pair{0.3, 1e5}, std::pair{0.5, 3e4}, std::pair{-0.2, 8e5}}) {
      const Model posed = stiffmsa::testing::two_joint_arm(x, k);
      const Result from_values = solve(structure, workspace, structure.values_of(posed), options);
      const Result fresh = solve(posed, options);
      ASSERT_TRUE(from_values.end_effectors[0].compliance && fresh.end_effectors[0].compliance);
      EXPECT_EQ(*from_values.end_effectors[0].compliance, *fresh.end_effectors[0].compliance) << x;
      EXPECT_EQ(*from_values.end_effectors[0].deflection, *fresh.end_effectors[0].deflection) << x;
      EXPECT_EQ(from_values.report.solver, fresh.report.solver);
    }
  }
}

// Per pose only values are checked, each defect at its key: a negative modulus, a spring that is
// not positive definite, a zero axis, a zero-length beam.
TEST(Structure, ValuesAreCheckedAtTheirKeys) {
  const Structure structure(stiffmsa::testing::two_joint_arm(0.3, 1e5));
  Workspace workspace(structure);
  const auto defect_of = [&](const std::string& slot, double value) {
    std::vector<double> values = structure.default_values();
    values[*structure.find_slot(slot)] = value;
    const auto defects = structure.find_value_defects(values);
    EXPECT_FALSE(defects.empty()) << slot;
    try {
      solve(workspace, values);
      ADD_FAILURE() << "solved with " << slot << " = " << value;
    } catch (const InputError& e) {
      EXPECT_EQ(e.diagnostics().front().key_path, defects.front().key_path);
    }
    return defects.empty() ? std::string() : defects.front().key_path;
  };
  EXPECT_EQ(defect_of("links.upper.material.E", -1), "links.upper.material.E");
  EXPECT_EQ(defect_of("joints.elbow.stiffness[0][0]", -5), "joints.elbow.stiffness");
  std::vector<double> zero_axis = structure.default_values();
  for (int i = 0; i < 3; ++i)
    zero_axis[*structure.find_slot("joints.shoulder.axis[" + std::to_string(i) + "]")] = 0;
  const auto axis_defects = structure.find_value_defects(zero_axis);
  ASSERT_FALSE(axis_defects.empty());
  EXPECT_EQ(axis_defects.front().key_path, "joints.shoulder.axis");
  std::vector<double> short_beam = structure.default_values();
  for (int i = 0; i < 3; ++i)
    short_beam[*structure.find_slot("points.B[" + std::to_string(i) + "]")] =
        short_beam[*structure.find_slot("points.A[" + std::to_string(i) + "]")];
  const auto length_defects = structure.find_value_defects(short_beam);
  ASSERT_FALSE(length_defects.empty());
  EXPECT_EQ(length_defects.front().key_path, "links.upper");
  EXPECT_TRUE(contains(length_defects.front().message, "zero length"))
      << length_defects.front().message;
  // A failed pose leaves nothing behind for the next.
  const Result after = solve(workspace, structure.default_values());
  EXPECT_EQ(*after.end_effectors[0].compliance,
            *solve(structure.model()).end_effectors[0].compliance);
}

TEST(Structure, AModelOfAnotherStructureIsRefused) {
  const Structure structure(stiffmsa::testing::two_joint_arm(0.3, 1e5));
  Model renamed = stiffmsa::testing::two_joint_arm(0.3, 1e5);
  renamed.links[1].name = "upper_arm";
  EXPECT_THROW(structure.values_of(renamed), InputError);
  Model other_kind = stiffmsa::testing::two_joint_arm(0.3, 1e5);
  other_kind.joints[0].connection.stiffness.reset();
  EXPECT_THROW(structure.values_of(other_kind), InputError);
  EXPECT_THROW(Structure(Model{}), InputError);  // validated when built: no links
}

TEST(Structure, AWorkspaceSolvesTheValuesOfItsOwnStructureOnly) {
  const Structure structure(stiffmsa::testing::two_joint_arm(0.3, 1e5)),
      other(stiffmsa::testing::two_joint_arm(0.3, 1e5));
  Workspace workspace(structure);
  EXPECT_THROW(solve(other, workspace, other.default_values()), UsageError);
  Workspace of_a_model(stiffmsa::testing::two_joint_arm(0.3, 1e5));
  EXPECT_THROW(solve(of_a_model, structure.default_values()), UsageError);
  std::vector<double> too_few(structure.value_count() - 1);
  EXPECT_THROW(solve(workspace, too_few), UsageError);
}

// A sweep is a function of a structure and value sets: solve_poses gives each pose what a
// single solve of its values gives.
TEST(Structure, SolvePosesMeasuresEachValueSet) {
  const Structure structure(stiffmsa::testing::two_joint_arm(0.3, 1e5));
  std::vector<double> sets;
  const std::vector<Model> posed{stiffmsa::testing::two_joint_arm(0.3, 1e5),
                                 stiffmsa::testing::two_joint_arm(0.45, 2e5),
                                 stiffmsa::testing::two_joint_arm(0.6, 5e4)};
  for (const Model& m : posed) {
    const auto values = structure.values_of(m);
    sets.insert(sets.end(), values.begin(), values.end());
  }
  std::vector<double> broken = structure.default_values();
  broken[*structure.find_slot("links.column.material.E")] = 0;
  sets.insert(sets.end(), broken.begin(), broken.end());
  SweepOptions options;
  options.threads = 2;
  options.keep_matrices = true;
  const std::vector<PoseResult> results = solve_poses(structure, sets, options);
  ASSERT_EQ(results.size(), 4u);
  for (std::size_t i = 0; i < posed.size(); ++i) {
    ASSERT_EQ(results[i].status, PoseStatus::ok) << results[i].message;
    EXPECT_EQ(*results[i].end_effectors[0].compliance,
              *solve(posed[i]).end_effectors[0].compliance);
  }
  EXPECT_EQ(results[3].status, PoseStatus::invalid);
  EXPECT_TRUE(contains(results[3].message, "links.column.material.E")) << results[3].message;
}

// A family of a plain function: members are its models; one of another structure is invalid.
TEST(Structure, AFamilyOfAPlainFunction) {
  const ModelFamily family(
      "arm", {{"x", 0.3, "m", {}}, {"k", 1e5, "N m/rad", {}}},
      [](std::span<const double> p) { return stiffmsa::testing::two_joint_arm(p[0], p[1]); });
  const Structure structure = family.structure();
  EXPECT_EQ(structure.values_of(family.build(std::vector<double>{0.4, 2e5})),
            structure.values_of(stiffmsa::testing::two_joint_arm(0.4, 2e5)));
  const SweepResult s = sweep(family, grid_poses({{"x", 0.2, 0.6, 3}}));
  ASSERT_EQ(s.results.size(), 3u);
  for (const PoseResult& r : s.results) EXPECT_EQ(r.status, PoseStatus::ok) << r.message;
}
