// Sweeps: every row equals an independent solve of its pose, whatever the threads and the
// order; failures become statuses; the CSV, pose and summary files say exactly that.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "stiffmsa/analysis.hpp"
#include "stiffmsa/io/model_file.hpp"
#include "stiffmsa/io/sweep_file.hpp"
#include "stiffmsa/sweep.hpp"

namespace stiffmsa {
namespace {

std::string example(const std::string& name) {
  return std::string(STIFFMSA_SOURCE_DIR) + "/examples/" + name;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

const ModelFamily& three_rpr() {
  static const ModelFamily family = load_model_family(example("planar-3rpr-parametric.yaml"));
  return family;
}

// Two pinned bars from A (-1, 0) and B (1, 0) meeting at P (0, h): a stiff triangle for h != 0,
// a mechanism for h = 0 (P can move along y to first order).
const char* const kTwoBarTruss = R"(format: stiffmsa/1
name: two-bar-truss
parameters:
  h: 0.5
  load: 0
materials:
  steel: {E: 2.1e11, nu: 0.3}
sections:
  bar: {shape: circle, D: 0.02}
points:
  A: [-1, 0, 0]
  B: [1, 0, 0]
  P: [0, h, 0]
links:
  left: {type: beam, from: A, to: P, material: steel, section: bar}
  right: {type: beam, from: B, to: P, material: steel, section: bar}
joints:
  pin: {type: revolute, at: P, links: [left, right], axis: [0, 0, 1]}
supports:
  a: {type: revolute, at: A, axis: [0, 0, 1]}
  b: {type: revolute, at: B, axis: [0, 0, 1]}
loads:
  - {at: P, link: left, wrench: [0, "-load", 0, 0, 0, 0]}
end_effectors:
  tip: {at: P, link: left}
)";

// A serial arm whose elbow moves with the parameters: a tree, which `auto` solves without
// factorising.
const char* const kSerialArm = R"(format: stiffmsa/1
name: serial-arm
parameters:
  px: 0.3
  py: 0.2
materials:
  aluminium: {E: 7.0e10, nu: 0.33}
sections:
  box: {shape: rect_tube, b: 0.06, h: 0.08, t: 0.004}
points:
  floor: [0, 0, -0.25]
  shoulder: [0, 0, 0]
  elbow: [px, py, 0.05]
  tip: ["px + 0.3", "py - 0.1", 0]
links:
  pedestal: {type: rigid, from: floor, to: shoulder}
  upper_arm: {type: beam, from: shoulder, to: elbow, material: aluminium, section: box}
  forearm: {type: beam, from: elbow, to: tip, material: aluminium, section: box}
joints:
  shoulder_joint: {type: revolute, at: shoulder, links: [pedestal, upper_arm], axis: [0, 0, 1], stiffness: 2.0e5}
  elbow_joint: {type: revolute, at: elbow, links: [upper_arm, forearm], axis: [0, 0, 1], stiffness: 1.0e5}
supports:
  base: {type: rigid, at: floor}
loads:
  - {at: tip, wrench: [50, -200, 0, 0, 0, 0]}
end_effectors:
  tool: {at: tip}
)";

// The measures a sweep reports, computed here from an independent solve of the pose: with a
// fresh workspace built from the family's defaults, as every sweep thread's is (its reference
// matrix fixes the scaling start and pivot order), and with no workspace at all.
struct Independent {
  PrincipalStiffness principal;
  double deflection_translation, deflection_rotation;
  Mat6 compliance;
  Mat6 one_shot_compliance;
};
Independent solve_alone(const ModelFamily& family, const std::vector<std::string>& swept,
                        std::span<const double> pose) {
  std::vector<double> values = family.default_values();
  for (std::size_t k = 0; k < swept.size(); ++k) values[*family.find_parameter(swept[k])] = pose[k];
  Workspace workspace(family.build(family.default_values()));
  const Result r = solve(workspace, family.build(values));
  const auto& e = r.end_effectors.front();
  return {principal_stiffness(*e.compliance), e.deflection->head<3>().norm(),
          e.deflection->tail<3>().norm(), *e.compliance,
          *solve(family.build(values)).end_effectors.front().compliance};
}

TEST(Grid, FirstAxisVariesFastestAndEndsAreExact) {
  const PoseTable t = grid_poses({{"x", -0.2, 0.1, 4}, {"y", 1, 2, 2}});
  ASSERT_EQ(t.size(), 8u);
  EXPECT_EQ(t.parameters, (std::vector<std::string>{"x", "y"}));
  const std::vector<double> expected{-0.2, 1, -0.1, 1, 0, 1, 0.1, 1,
                                     -0.2, 2, -0.1, 2, 0, 2, 0.1, 2};
  ASSERT_EQ(t.values.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i)
    EXPECT_NEAR(t.values[i], expected[i], 1e-15) << i;
  EXPECT_EQ(t.pose(3)[0], 0.1);  // the stop exactly as written
  EXPECT_EQ(grid_poses({{"x", 7, 9, 1}}).values, std::vector<double>{7});
}

TEST(Grid, RefusesEmptyRepeatedAndHugeGrids) {
  EXPECT_THROW(grid_poses({{"x", 0, 1, 0}}), UsageError);
  EXPECT_THROW(grid_poses({{"x", 0, 1, 3}, {"x", 0, 1, 3}}), UsageError);
  EXPECT_THROW(grid_poses({{"x", 0, 1, 100000}, {"y", 0, 1, 100000}}), UsageError);
  EXPECT_THROW(grid_poses({{"x", 0, NAN, 3}}), UsageError);
}

TEST(Sweep, EveryRowEqualsAnIndependentSolve) {
  const PoseTable poses =
      grid_poses({{"x", 0.3, 0.6, 4}, {"y", 0.2, 0.45, 3}, {"phi", 0.0, 0.3, 2}});
  SweepOptions options;
  options.keep_matrices = true;
  const SweepResult s = sweep(three_rpr(), poses, options);
  ASSERT_EQ(s.results.size(), 24u);
  EXPECT_EQ(s.end_effectors, std::vector<std::string>{"platform"});
  EXPECT_EQ(s.units, (std::vector<std::string>{"m", "m", "rad"}));
  for (std::size_t i = 0; i < poses.size(); ++i) {
    ASSERT_EQ(s.results[i].status, PoseStatus::ok) << i << ": " << s.results[i].message;
    const Independent alone = solve_alone(three_rpr(), poses.parameters, poses.pose(i));
    const EndEffectorMeasures& m = s.results[i].end_effectors[0];
    // The same arithmetic on the same numbers: equal to the last bit, not just close.
    EXPECT_EQ(m.principal.translational, alone.principal.translational) << i;
    EXPECT_EQ(m.principal.rotational, alone.principal.rotational) << i;
    EXPECT_EQ(m.deflection_translation, alone.deflection_translation) << i;
    EXPECT_EQ(m.deflection_rotation, alone.deflection_rotation) << i;
    EXPECT_EQ(*m.compliance, alone.compliance) << i;
    // Solved alone, the pose may be pivoted otherwise: the same to rounding.
    EXPECT_LT((*m.compliance - alone.one_shot_compliance).cwiseAbs().maxCoeff(),
              1e-13 * alone.one_shot_compliance.cwiseAbs().maxCoeff())
        << i;
  }
}

class SweepWithEverySolver : public ::testing::TestWithParam<SolverKind> {};

TEST_P(SweepWithEverySolver, ResultDoesNotDependOnThreadsOrPoseOrder) {
  if (!solver_available(GetParam())) GTEST_SKIP() << to_string(GetParam()) << " is not built in";
  const PoseTable forward = grid_poses({{"px", 0.1, 0.4, 9}, {"py", 0.1, 0.4, 8}});
  PoseTable backward = forward;
  backward.grid.clear();
  const std::size_t n = forward.size(), k = forward.parameters.size();
  for (std::size_t i = 0; i < n; ++i)
    std::copy_n(forward.values.begin() + static_cast<long>((n - 1 - i) * k), k,
                backward.values.begin() + static_cast<long>(i * k));
  // A parallel robot (factorised by every solver) and a serial arm (a tree solve under auto).
  for (const ModelFamily& family : {load_model_family(example("tripteron-parametric.yaml")),
                                    parse_model_family(kSerialArm, "arm.yaml")}) {
    SCOPED_TRACE(family.name());
    if (family.name() == "serial-arm" && GetParam() == SolverKind::automatic)
      EXPECT_EQ(solve(family.build(family.default_values())).report.solver,
                stiffmsa::SolverUsed::tree);
    SweepOptions one, two;
    one.threads = 1;
    two.threads = 2;
    one.solve.solver = two.solve.solver = GetParam();
    one.keep_matrices = two.keep_matrices = true;
    const SweepResult a = sweep(family, forward, one);
    const SweepResult b = sweep(family, forward, two);
    const SweepResult c = sweep(family, backward, two);
    // The threads that took part: on a busy machine a fast sweep can be done before the second
    // one starts.
    EXPECT_GE(b.threads, 1u);
    EXPECT_LE(b.threads, 2u);
    std::size_t ok = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const PoseResult& ra = a.results[i];
      for (const PoseResult* other : {&b.results[i], &c.results[n - 1 - i]}) {
        ASSERT_EQ(other->status, ra.status) << i;
        EXPECT_EQ(other->message, ra.message) << i;
        if (ra.status != PoseStatus::ok) continue;
        EXPECT_EQ(*other->end_effectors[0].compliance, *ra.end_effectors[0].compliance) << i;
        EXPECT_EQ(other->end_effectors[0].deflection_translation,
                  ra.end_effectors[0].deflection_translation)
            << i;
      }
      ok += ra.status == PoseStatus::ok ? 1 : 0;
    }
    EXPECT_GT(ok, n / 2);  // the comparison covered real solves
    EXPECT_EQ(sweep_to_csv(a, true), sweep_to_csv(b, true));
  }
}

INSTANTIATE_TEST_SUITE_P(Solvers, SweepWithEverySolver,
                         ::testing::Values(SolverKind::automatic, SolverKind::sparse_lu,
                                           SolverKind::umfpack, SolverKind::klu),
                         [](const auto& info) { return std::string(to_string(info.param)); });

TEST(Sweep, AFunctionThatThrowsFailsOnlyItsPose) {
  const ModelFamily base = parse_model_family(kTwoBarTruss, "truss.yaml");
  const ModelFamily family("picky", base.parameters(), [&base](std::span<const double> v) {
    if (v[0] == 0.25) throw std::runtime_error("no model at h = 0.25");
    return base.build(v);
  });
  const SweepResult s = sweep(family, grid_poses({{"h", 0.25, 0.5, 2}}));
  EXPECT_EQ(s.results[0].status, PoseStatus::invalid);
  EXPECT_TRUE(contains(s.results[0].message, "no model at h = 0.25")) << s.results[0].message;
  EXPECT_EQ(s.results[1].status, PoseStatus::ok) << s.results[1].message;
}

TEST(Sweep, UnreachablePosesAreInvalidAndTheSweepGoesOn) {
  const ModelFamily family = load_model_family(example("tripteron-parametric.yaml"));
  const SweepResult s = sweep(family, grid_poses({{"px", 0.3, 0.7, 3}}));
  EXPECT_EQ(s.results[0].status, PoseStatus::ok) << s.results[0].message;
  EXPECT_EQ(s.results[1].status, PoseStatus::invalid);
  EXPECT_TRUE(contains(s.results[1].message, "derived.")) << s.results[1].message;
  EXPECT_TRUE(contains(s.results[1].message, "gives nan for L1 = 0.25")) << s.results[1].message;
  EXPECT_TRUE(s.results[1].end_effectors.empty());
  EXPECT_EQ(s.results[2].status, PoseStatus::invalid);
}

TEST(Sweep, AMechanismPoseIsAFreeMotion) {
  const ModelFamily family = parse_model_family(kTwoBarTruss, "truss.yaml");
  for (double load : {0.0, 10.0}) {
    SweepResult s = sweep(family.with_defaults(std::vector<double>{0.5, load}),
                          grid_poses({{"h", -0.5, 0.5, 3}}));
    EXPECT_EQ(s.results[0].status, PoseStatus::ok) << s.results[0].message;
    EXPECT_EQ(s.results[1].status, PoseStatus::free_motion) << load;
    EXPECT_FALSE(s.results[1].message.empty());
    EXPECT_EQ(s.results[2].status, PoseStatus::ok);
    // Mirror images: the same stiffness.
    EXPECT_NEAR(s.results[0].end_effectors[0].principal.translational(0),
                s.results[2].end_effectors[0].principal.translational(0),
                1e-9 * s.results[2].end_effectors[0].principal.translational(0));
  }
}

TEST(Sweep, FailedAccuracyChecksMakeAnInaccuratePose) {
  SweepOptions options;
  options.solve.max_relative_residual = 1e-300;  // no floating-point solve meets this
  const SweepResult s = sweep(three_rpr(), grid_poses({{"x", 0.4, 0.5, 2}}), options);
  for (const auto& r : s.results) {
    EXPECT_EQ(r.status, PoseStatus::inaccurate);
    EXPECT_STREQ(to_string(r.status), "inaccurate");
    EXPECT_TRUE(contains(r.message, "residual")) << r.message;
  }
}

TEST(Sweep, TopologyChangeIsAnInvalidPose) {
  // A family of the caller's whose second link appears only for n > 0.5.
  const auto make = [](std::span<const double> v) {
    Model m;
    m.add_point("a", Vec3::Zero());
    m.add_point("b", Vec3(1, 0, 0));
    m.add_beam("l1", "a", "b", {2.1e11, 0.3, {}}, Section::circle(0.02));
    if (v[0] > 0.5) {
      m.add_point("c", Vec3(2, 0, 0));
      m.add_beam("l2", "b", "c", {2.1e11, 0.3, {}}, Section::circle(0.02));
      m.add_end_effector("tip", "c");
    } else {
      m.add_end_effector("tip", "b");
    }
    m.add_support("clamp", "a", {}, Connection::rigid());
    return m;
  };
  const ModelFamily family("grows", {{"n", 0, "", {}}}, ModelFamily::MemberFunction(make));
  const SweepResult s = sweep(family, grid_poses({{"n", 0, 1, 2}}));
  EXPECT_EQ(s.results[0].status, PoseStatus::ok) << s.results[0].message;
  EXPECT_EQ(s.results[1].status, PoseStatus::invalid);
  EXPECT_TRUE(contains(s.results[1].message, "topology")) << s.results[1].message;
}

TEST(Sweep, UnknownParameterIsANameError) {
  try {
    sweep(three_rpr(), grid_poses({{"xx", 0, 1, 2}}));
    FAIL() << "swept a parameter the model does not have";
  } catch (const NameError& e) {
    EXPECT_TRUE(contains(e.what(), "the model 'planar-3rpr-parametric' (" +
                                       example("planar-3rpr-parametric.yaml") +
                                       ") has no parameter 'xx'"))
        << e.what();
    EXPECT_TRUE(contains(e.what(), "did you mean 'x'")) << e.what();
    EXPECT_EQ(e.kind(), "parameter");
    EXPECT_EQ(e.name(), "xx");
    EXPECT_EQ(e.suggestion(), "x");
  }
}

// The library names its own option; the command puts its flag (--case) in its place.
TEST(Sweep, UnknownLoadCaseIsAUsageErrorNamingTheOption) {
  SweepOptions options;
  options.load_case = "up";
  try {
    sweep(three_rpr(), grid_poses({{"x", 0.4, 0.5, 2}}), options);
    FAIL() << "swept a load case the model does not have";
  } catch (const UsageError& e) {
    EXPECT_TRUE(contains(e.what(), "SweepOptions::load_case 'up'")) << e.what();
    EXPECT_TRUE(contains(e.what(), "it names no load case")) << e.what();
    EXPECT_FALSE(contains(e.what(), "--")) << e.what();
  }
}

TEST(Sweep, ProgressReachesTheEnd) {
  std::size_t last_done = 0, calls = 0, total_seen = 0;
  SweepOptions options;
  options.progress = [&](std::size_t done, std::size_t total) {
    ++calls;
    last_done = done;
    total_seen = total;
  };
  sweep(three_rpr(), grid_poses({{"x", 0.3, 0.6, 10}}), options);
  EXPECT_GE(calls, 1u);
  EXPECT_EQ(last_done, 10u);
  EXPECT_EQ(total_seen, 10u);
}

// ---- the examples' maps against theory ------------------------------------------------------

// The 3-RPR loses its rotational stiffness where the three leg lines meet in one point (a
// parallel singularity): there, the lines' homogeneous coordinates are linearly dependent.
double leg_line_concurrency(double x, double y, double phi) {
  const double r = 0.12;
  const Vec3 base[3] = {{0, 0, 1}, {1, 0, 1}, {0.5, 0.9, 1}};
  Mat3 lines;
  for (int i = 0; i < 3; ++i) {
    const double angle = phi + (i - 1) * 2 * M_PI / 3;
    const Vec3 corner(x + r * std::cos(angle), y + r * std::sin(angle), 1);
    lines.row(i) = base[i].cross(corner).normalized().transpose();
  }
  return lines.determinant();
}

TEST(ExampleMaps, ThreeRprIsSoftestWhereItsLegLinesMeet) {
  const GridAxis phi{"phi", -1.2, 1.2, 241};
  const SweepResult s = sweep(three_rpr(), grid_poses({phi}));
  std::vector<double> k_rot;
  std::size_t softest = 0;
  for (std::size_t i = 0; i < s.results.size(); ++i) {
    ASSERT_EQ(s.results[i].status, PoseStatus::ok) << i;
    k_rot.push_back(s.results[i].end_effectors[0].principal.rotational(0));
    if (k_rot[i] < k_rot[softest]) softest = i;
  }
  // The singular orientation, found independently: where the concurrency changes sign.
  double singular_phi = NAN;
  for (std::size_t i = 0; i + 1 < phi.count; ++i) {
    const double a = leg_line_concurrency(0.46, 0.33, phi.value(i));
    const double b = leg_line_concurrency(0.46, 0.33, phi.value(i + 1));
    if (a * b <= 0) singular_phi = phi.value(i) - a * (phi.value(i + 1) - phi.value(i)) / (b - a);
  }
  ASSERT_FALSE(std::isnan(singular_phi)) << "no singular orientation in the swept range";
  const double step = (phi.stop - phi.start) / static_cast<double>(phi.count - 1);
  EXPECT_LE(std::abs(phi.value(softest) - singular_phi), step)
      << phi.value(softest) << " vs " << singular_phi;
  std::vector<double> sorted = k_rot;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2),
                   sorted.end());
  EXPECT_LT(k_rot[softest], 1e-3 * sorted[sorted.size() / 2]);  // decades below the typical pose
}

TEST(ExampleMaps, TripteronSoftensAsItsLegsStretch) {
  // Along the diagonal px = py every leg reaches further as t grows.
  PoseTable diagonal{{"px", "py"}, {}, {}};
  for (double t = 0.18; t < 0.385; t += 0.04) diagonal.values.insert(diagonal.values.end(), {t, t});
  const SweepResult s = sweep(load_model_family(example("tripteron-parametric.yaml")), diagonal);
  for (std::size_t i = 1; i < s.results.size(); ++i)
    EXPECT_LT(s.results[i].end_effectors[0].principal.translational(0),
              s.results[i - 1].end_effectors[0].principal.translational(0))
        << "at t = " << diagonal.pose(i)[0];
  EXPECT_LT(s.results.back().end_effectors[0].principal.translational(0),
            0.7 * s.results.front().end_effectors[0].principal.translational(0));
}

// ---- files ---------------------------------------------------------------------------------

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  for (std::size_t end; (end = line.find(separator, start)) != std::string::npos; start = end + 1)
    fields.push_back(line.substr(start, end - start));
  fields.push_back(line.substr(start));
  return fields;
}

TEST(SweepCsv, HeaderRowsAndValuesReadBackExactly) {
  const ModelFamily family = load_model_family(example("tripteron-parametric.yaml"));
  const SweepResult s = sweep(family, grid_poses({{"px", 0.3, 0.7, 3}}));
  const auto lines = split(sweep_to_csv(s, false), '\n');
  ASSERT_EQ(lines.size(), 5u);  // header, 3 rows, and the empty text after the last newline
  EXPECT_EQ(lines[0],
            "px,status,message,platform.k_trans_min,platform.k_trans_max,platform.k_rot_min,"
            "platform.k_rot_max,"
            "platform.deflection_trans,platform.deflection_rot,platform.cond_trans");
  const auto row = split(lines[1], ',');
  ASSERT_EQ(row.size(), 10u);
  EXPECT_EQ(row[0], "0.3");
  EXPECT_EQ(row[1], "ok");
  const auto columns = sweep_columns(s, false);
  for (std::size_t c = 0; c < columns.size(); ++c)
    EXPECT_EQ(std::stod(row[3 + c]), column_value(s, columns[c], 0)) << c;
  // The invalid row: its message is quoted (it has commas) and its values are empty.
  EXPECT_TRUE(contains(lines[2], "0.5,invalid,\"")) << lines[2];
  EXPECT_TRUE(lines[2].ends_with(",,,,,,,")) << lines[2];
}

TEST(SweepCsv, FullAddsTheMatricesWithUnits) {
  const SweepResult s =
      sweep(three_rpr(), grid_poses({{"x", 0.4, 0.5, 2}}), SweepOptions{.keep_matrices = true});
  const auto columns = sweep_columns(s, true);
  ASSERT_EQ(columns.size(), 7u + 72u);
  EXPECT_EQ(columns[7].name, "platform.C11");
  EXPECT_EQ(columns[7].unit, "m/N");
  EXPECT_EQ(columns[7 + 35].name, "platform.C66");
  EXPECT_EQ(columns[7 + 35].unit, "rad/(N·m)");
  EXPECT_EQ(columns[7 + 36 + 3].name, "platform.K14");
  EXPECT_EQ(columns[7 + 36 + 3].unit, "N/rad");
  const auto header = split(split(sweep_to_csv(s, true), '\n')[0], ',');
  EXPECT_EQ(header.size(), 3u + 79u);
  const auto row = split(split(sweep_to_csv(s, true), '\n')[1], ',');
  const Mat6 C = *s.results[0].end_effectors[0].compliance;
  EXPECT_EQ(std::stod(row[3 + 7 + 5]), C(0, 5));  // C16
}

TEST(SweepSummary, NamesTheWorstPosePerColumn) {
  const SweepResult s = sweep(three_rpr(), grid_poses({{"x", 0.2, 0.7, 6}, {"y", 0.15, 0.5, 4}}));
  const auto summary = nlohmann::json::parse(sweep_summary_to_json(s, false, "map.csv"));
  EXPECT_EQ(summary["format"], "stiffmsa-sweep/1");
  EXPECT_EQ(summary["csv"], "map.csv");
  EXPECT_EQ(summary["poses"], 24);
  EXPECT_EQ(summary["status"]["ok"], 24);
  EXPECT_EQ(summary["parameters"][1]["grid"]["count"], 4);
  // The softest pose by brute force.
  std::size_t softest = 0;
  for (std::size_t i = 1; i < s.results.size(); ++i)
    if (s.results[i].end_effectors[0].principal.translational(0) <
        s.results[softest].end_effectors[0].principal.translational(0))
      softest = i;
  const auto& worst = summary["worst"]["platform.k_trans_min"];
  EXPECT_EQ(worst["pose"], softest);
  EXPECT_EQ(worst["csv_line"], softest + 2);
  EXPECT_EQ(worst["criterion"], "smallest");
  EXPECT_EQ(worst["value"].get<double>(),
            s.results[softest].end_effectors[0].principal.translational(0));
  EXPECT_EQ(worst["parameters"]["x"].get<double>(), s.poses.pose(softest)[0]);
  EXPECT_EQ(summary["worst"]["platform.deflection_trans"]["criterion"], "largest");
}

TEST(PoseFile, ReadsHeaderRowsCommentsAndBlankLines) {
  const PoseTable t = parse_pose_table("# poses\nx, y\n0.1,0.2\n\n-3e-1 , 4\n", "poses.csv");
  EXPECT_EQ(t.parameters, (std::vector<std::string>{"x", "y"}));
  EXPECT_EQ(t.values, (std::vector<double>{0.1, 0.2, -0.3, 4}));
  EXPECT_TRUE(t.grid.empty());
}

TEST(PoseFile, ReadsWhatSpreadsheetsWrite) {
  const PoseTable t = parse_pose_table("\xEF\xBB\xBF\"x\",\"y\"\r\n\"0.1\",0.2\r\n", "poses.csv");
  EXPECT_EQ(t.parameters, (std::vector<std::string>{"x", "y"}));
  EXPECT_EQ(t.values, (std::vector<double>{0.1, 0.2}));
}

TEST(PoseFile, DefectsNameTheLineAndColumn) {
  try {
    parse_pose_table("x,y\n0.1,0.2\n0.3\n0.4,abc\n", "poses.csv");
    FAIL();
  } catch (const InputError& e) {
    ASSERT_EQ(e.diagnostics().size(), 2u);
    EXPECT_EQ(e.diagnostics()[0].location.line, 3);
    EXPECT_TRUE(contains(e.diagnostics()[0].message, "expected 2 values")) << e.what();
    EXPECT_EQ(e.diagnostics()[1].location.line, 4);
    EXPECT_EQ(e.diagnostics()[1].key_path, "y");
    EXPECT_TRUE(contains(e.diagnostics()[1].message, "'abc'")) << e.what();
  }
  EXPECT_THROW(parse_pose_table("", "p.csv"), InputError);
  EXPECT_THROW(parse_pose_table("x,x\n1,2\n", "p.csv"), InputError);
  EXPECT_THROW(parse_pose_table("x\n", "p.csv"), InputError);
  EXPECT_THROW(parse_pose_table("x\ninf\n", "p.csv"), InputError);
}

TEST(PoseFile, PlainNumbersAreWholeFiniteDecimals) {
  EXPECT_EQ(parse_plain_number("+1.5"), 1.5);
  EXPECT_EQ(parse_plain_number("-2e-3"), -2e-3);
  for (const char* text : {"", "+", "1.5x", " 1", "nan", "inf", "1e999", "0x10", "--1", "+-1"})
    EXPECT_FALSE(parse_plain_number(text).has_value()) << text;
}

TEST(PoseFile, SweepOverListedPosesMatchesTheGrid) {
  const PoseTable listed = parse_pose_table("y,x\n0.3,0.5\n0.2,0.4\n", "p.csv");
  const SweepResult s = sweep(three_rpr(), listed);
  const Independent alone = solve_alone(three_rpr(), {"x", "y"}, std::vector<double>{0.4, 0.2});
  EXPECT_EQ(s.results[1].end_effectors[0].principal.translational, alone.principal.translational);
}

}  // namespace
}  // namespace stiffmsa
