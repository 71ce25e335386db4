// A model compiled into its structure and its values: slots named by their keys, a pose solved
// from values alone with the numbers of a fresh solve, and per-pose checks of values only.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

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

namespace {

// A beam with every issue-22 number: a density, a settlement, loads along it, gravity and two
// named load cases.
Model loaded_beam() {
  Model m;
  m.add_point("O", Vec3::Zero());
  m.add_point("E", Vec3(1, 0, 0));
  Material steel{2.1e11, 0.3, std::nullopt, 7850.0};
  m.add_beam("L", "O", "E", steel, Section::circle(0.02));
  const auto clamp = m.add_support("S", "O", {}, Connection::rigid());
  m.support(clamp).displacement = (Vec6() << 0, 0, -0.001, 0, 0, 0).finished();
  m.add_load("E", std::nullopt, (Vec6() << 0, 0, -10, 0, 0, 0).finished());
  m.add_link_load("L", DistributedLinkLoad{Vec3(0, 0, -100), Vec3(0, 0, -300)});
  m.add_link_load("L", PointLinkLoad{Vec3(0, 0, -50), Vec3(0, 5, 0), 0.3});
  m.gravity = Vec3(0, 0, -9.81);
  LoadCase heavy;
  heavy.name = "heavy";
  heavy.loads.push_back(
      Load{"E", std::nullopt, (Vec6() << 1, 2, 3, 4, 5, 6).finished(), false, {}});
  heavy.link_loads.push_back(LinkLoad{"L", PointLinkLoad{Vec3(0, 1, 0), Vec3::Zero(), 0.5}, {}});
  heavy.gravity = Vec3(0, 0, -19.62);
  m.add_load_case(heavy);
  LoadCase along;
  along.name = "along";
  along.link_loads.push_back(LinkLoad{"L", DistributedLinkLoad{Vec3(0, 7, 0), Vec3(0, 7, 0)}, {}});
  m.add_load_case(along);
  m.add_end_effector("tip", "E");
  return m;
}

}  // namespace

TEST(Structure, IssueTwentyTwoNumbersHaveNamedSlots) {
  const Structure structure(loaded_beam());
  const auto value = [&](const std::string& name) {
    const auto slot = structure.find_slot(name);
    EXPECT_TRUE(slot) << name;
    return slot ? structure.default_values()[*slot] : std::nan("");
  };
  EXPECT_EQ(value("links.L.material.density"), 7850.0);
  EXPECT_EQ(value("supports.S.displacement[2]"), -0.001);
  EXPECT_EQ(value("link_loads[0].distributed.from[2]"), -100.0);
  EXPECT_EQ(value("link_loads[0].distributed.to[2]"), -300.0);
  EXPECT_EQ(value("link_loads[1].force[2]"), -50.0);
  EXPECT_EQ(value("link_loads[1].moment[1]"), 5.0);
  EXPECT_EQ(value("link_loads[1].position"), 0.3);
  EXPECT_EQ(value("gravity[2]"), -9.81);
  EXPECT_EQ(value("load_cases.heavy.loads[0].wrench[2]"), 3.0);
  EXPECT_EQ(value("load_cases.heavy.link_loads[0].force[1]"), 1.0);
  EXPECT_EQ(value("load_cases.heavy.link_loads[0].position"), 0.5);
  EXPECT_EQ(value("load_cases.heavy.gravity[2]"), -19.62);
  EXPECT_EQ(value("load_cases.along.link_loads[0].distributed.to[1]"), 7.0);
  EXPECT_FALSE(structure.find_slot("load_cases.along.gravity[2]"));
  // The names are unique: each says which number it is.
  auto names = structure.slot_names();
  std::sort(names.begin(), names.end());
  EXPECT_EQ(std::adjacent_find(names.begin(), names.end()), names.end());
}

TEST(Structure, IssueTwentyTwoNumbersRoundTripThroughTheirSlots) {
  const Structure structure(loaded_beam());
  std::vector<double> values = structure.default_values();
  for (std::size_t i = 0; i < values.size(); ++i) values[i] += 0.25 * static_cast<double>(i + 1);
  const Model changed = structure.model_with(values);
  EXPECT_EQ(structure.values_of(changed), values);
  EXPECT_EQ(changed.gravity->z(), values[*structure.find_slot("gravity[2]")]);
  EXPECT_EQ(std::get<PointLinkLoad>(changed.load_cases[0].link_loads[0].load).position,
            values[*structure.find_slot("load_cases.heavy.link_loads[0].position")]);
  Model written = structure.model();
  structure.write_values(values, written);
  EXPECT_EQ(structure.values_of(written), values);
  EXPECT_EQ((*written.supports[0].displacement)(2),
            values[*structure.find_slot("supports.S.displacement[2]")]);
}

// A present or absent optional (a density, a settlement, gravity, a case, a load along a link
// or its kind) is structure: its numbers would fill other slots.
TEST(Structure, IssueTwentyTwoOptionalsAreStructure) {
  const Structure structure(loaded_beam());
  const auto refused = [&](const std::function<void(Model&)>& change) {
    Model m = loaded_beam();
    change(m);
    try {
      structure.values_of(m);
    } catch (const InputError& e) {
      return contains(e.what(), "structure differs");
    }
    return false;
  };
  EXPECT_FALSE(refused([](Model&) {}));
  EXPECT_TRUE(
      refused([](Model& m) { std::get<BeamLink>(m.links[0].kind).material.density.reset(); }));
  EXPECT_TRUE(refused([](Model& m) { m.supports[0].displacement.reset(); }));
  EXPECT_TRUE(refused([](Model& m) { m.gravity.reset(); }));
  EXPECT_TRUE(refused([](Model& m) { m.load_cases[0].gravity.reset(); }));
  EXPECT_TRUE(refused([](Model& m) { m.load_cases.pop_back(); }));
  EXPECT_TRUE(refused([](Model& m) { m.load_cases[1].name = "sideways"; }));
  EXPECT_TRUE(refused([](Model& m) { m.link_loads.pop_back(); }));
  EXPECT_TRUE(refused([](Model& m) { m.link_loads[1].load = DistributedLinkLoad{}; }));
  EXPECT_TRUE(refused([](Model& m) { m.load_cases[0].loads[0].at = "O"; }));
  EXPECT_TRUE(refused([](Model& m) { m.options.mode = AnalysisMode::loaded; }));
}
