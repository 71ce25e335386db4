// Plausibility warnings (docs/model-format.md, "Plausibility warnings"), the stiffness a
// designer reads beside the principal values (principal directions, stiffness along a
// direction, the translational condition), what a result records of its parameters, and the
// one number formatter. Deflections are pinned against the cantilever's closed forms, so that
// each threshold is tested just above and just below.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "analysis/plausibility.hpp"
#include "stiffmsa/stiffmsa.hpp"

namespace {

namespace fs = std::filesystem;
using namespace stiffmsa;

constexpr double kTolerance = 1e-9;

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

bool any_contains(const std::vector<std::string>& texts, const std::string& part) {
  return std::any_of(texts.begin(), texts.end(),
                     [&](const std::string& t) { return contains(t, part); });
}

// A steel rod of 1 m along x, clamped at O; `material`, `section` and the tip load as given.
std::string cantilever(const std::string& material, const std::string& section,
                       const std::string& wrench, const std::string& tip = "[1, 0, 0]") {
  return "format: stiffmsa/1\nname: rod\npoints:\n  O: [0, 0, 0]\n  E: " + tip +
         "\nlinks:\n  L1:\n    type: beam\n    from: O\n    to: E\n    material: " + material +
         "\n    section: " + section +
         "\nsupports:\n  S1: {type: rigid, at: O, link: L1}\nloads:\n  - {at: E, link: L1, "
         "wrench: " +
         wrench + "}\nend_effectors:\n  EE: {at: E, link: L1}\n";
}

constexpr const char* steel = "{E: 2.1e11, nu: 0.3}";
constexpr const char* rod_section = "{shape: circle, D: 0.05}";
constexpr double youngs_modulus = 2.1e11, diameter = 0.05, length = 1.0;
const double second_moment = std::numbers::pi * std::pow(diameter, 4) / 64;
const double area = std::numbers::pi * diameter * diameter / 4;

std::string number(double value) { return shortest_text(value); }

// The warnings that are plausibility warnings (and not, say, a condition warning).
std::vector<std::string> plausibility_warnings(const Result& result) {
  std::vector<std::string> found;
  for (const auto& w : result.report.warnings)
    if (contains(w, "engineering materials") || contains(w, "millimetres") ||
        contains(w, "linear method"))
      found.push_back(w);
  return found;
}

// ---- every example, at its defaults -----------------------------------------------------------

std::vector<fs::path> example_files() {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(fs::path(STIFFMSA_SOURCE_DIR) / "examples"))
    if (entry.path().extension() == ".yaml") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(Plausibility, EveryExampleAtItsDefaultsHasNoWarning) {
  const auto files = example_files();
  ASSERT_GE(files.size(), 8u);
  for (const auto& file : files) {
    const ModelFamily family = load_model_family(file);
    const Model model = family.build(family.default_values());
    EXPECT_TRUE(find_implausible_values(model).empty()) << file;
    const Result result = solve(model);
    EXPECT_TRUE(plausibility_warnings(result).empty())
        << file << ": " << result.report.warnings.front();
    EXPECT_TRUE(result.report.large_deflection.empty()) << file;
  }
}

// ---- moduli, sizes and sections ---------------------------------------------------------------

TEST(Plausibility, AModulusInMegapascalsIsNamedWithItsKeyAndLikelyCause) {
  const Model model = parse_model(
      cantilever("{E: 70000, nu: 0.3}", rod_section, "[0, -100, 0, 0, 0, 0]"), "mpa.yaml");
  const auto found = find_implausible_values(model);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].key_path, "links.L1.material.E");
  EXPECT_EQ(found[0].location.file, "mpa.yaml");
  EXPECT_GT(found[0].location.line, 0);
  EXPECT_EQ(found[0].message,
            "E = 70000 Pa is below the moduli of engineering materials (1e8 to 1e12 Pa): was it "
            "given in MPa or N/mm²? "
            "stiffmsa reads pascals (steel: E = 2.1e11 Pa)");
  // A warning, never an error: the model solves, and the 174-metre kind of deflection is named too.
  const Result result = solve(model);
  ASSERT_TRUE(result.end_effectors[0].stiffness);
  EXPECT_TRUE(any_contains(result.report.warnings, "links.L1.material.E: E = 70000 Pa"));
  EXPECT_TRUE(contains(result.report.large_deflection, "link end 'L1.to' turns"))
      << result.report.large_deflection;
}

TEST(Plausibility, ModuliAboveTheRangeAndShearModuliAreCheckedToo) {
  const auto high = find_implausible_values(
      parse_model(cantilever("{E: 2.1e14, nu: 0.3}", rod_section, "[0, 0, 0, 0, 0, 0]"), "m.yaml"));
  ASSERT_EQ(high.size(), 1u);
  EXPECT_TRUE(contains(high[0].message, "E = 2.1e+14 Pa is above the moduli")) << high[0].message;
  const auto shear = find_implausible_values(parse_model(
      cantilever("{E: 2.1e11, G: 80000}", rod_section, "[0, 0, 0, 0, 0, 0]"), "m.yaml"));
  ASSERT_EQ(shear.size(), 1u);
  EXPECT_EQ(shear[0].key_path, "links.L1.material.G");
  // The ends of the range are plausible.
  EXPECT_TRUE(
      find_implausible_values(
          parse_model(cantilever("{E: 1e12, G: 1e8}", rod_section, "[0, 0, 0, 0, 0, 0]"), "m.yaml"))
          .empty());
}

TEST(Plausibility, CoordinatesInMillimetresAreNamed) {
  const auto found = find_implausible_values(
      parse_model(cantilever(steel, rod_section, "[0, 0, 0, 0, 0, 0]", "[1200, 0, 0]"), "mm.yaml"));
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].key_path, "points");
  EXPECT_EQ(found[0].message,
            "the model is 1200 m across (the diagonal of its points' box): were the coordinates "
            "given in millimetres? "
            "stiffmsa reads metres");
  // 100 m is still a (large) structure.
  EXPECT_TRUE(find_implausible_values(
                  parse_model(cantilever(steel, rod_section, "[0, 0, 0, 0, 0, 0]", "[100, 0, 0]"),
                              "m.yaml"))
                  .empty());
}

TEST(Plausibility, SectionsInMillimetresAreNamed) {
  const auto circle = find_implausible_values(parse_model(
      cantilever(steel, "{shape: tube, D: 60, t: 4}", "[0, 0, 0, 0, 0, 0]"), "mm.yaml"));
  ASSERT_EQ(circle.size(), 1u);  // the wall is not an outer size
  EXPECT_EQ(circle[0].key_path, "links.L1.section.D");
  EXPECT_EQ(circle[0].message,
            "D = 60 m gives a section as wide as the link is long (1 m): was it given in "
            "millimetres? stiffmsa reads metres");
  const auto generic = find_implausible_values(
      parse_model(cantilever(steel, "{shape: generic, A: 1963, Iy: 3e5, Iz: 3e5, J: 6e5}",
                             "[0, 0, 0, 0, 0, 0]"),
                  "mm.yaml"));
  ASSERT_EQ(generic.size(), 1u);
  EXPECT_EQ(generic[0].key_path, "links.L1.section.A");
  EXPECT_TRUE(contains(generic[0].message, "A = 1963 m² gives a section about 44.3"))
      << generic[0].message;
  // A short piece of a finely divided beam is as wide as it is long, in metres all the same.
  EXPECT_TRUE(
      find_implausible_values(parse_model(cantilever(steel, "{shape: circle, D: 0.08}",
                                                     "[0, 0, 0, 0, 0, 0]", "[0.0004, 0, 0]"),
                                          "m.yaml"))
          .empty());
}

TEST(Plausibility, AValueSharedByManyLinksIsOneWarningThatCountsThem) {
  const Model model = parse_model(R"(format: stiffmsa/1
materials:
  soft: {E: 70000, nu: 0.3}
points: {O: [0, 0, 0], A: [1, 0, 0], B: [2, 0, 0], C: [3, 0, 0]}
links:
  a: {type: beam, from: O, to: A, material: soft, section: {shape: circle, D: 0.05}}
  b: {type: beam, from: A, to: B, material: soft, section: {shape: circle, D: 0.05}}
  c: {type: beam, from: B, to: C, material: soft, section: {shape: circle, D: 0.05}}
joints:
  ab: {type: rigid, at: A, links: [a, b]}
  bc: {type: rigid, at: B, links: [b, c]}
supports:
  S: {type: rigid, at: O}
)",
                                  "shared.yaml");
  const auto found = find_implausible_values(model);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].key_path, "links.a.material.E");
  EXPECT_TRUE(contains(found[0].message, "(and 2 other links)")) << found[0].message;
}

TEST(Plausibility, ASweepReportsTheWarningsOfItsModelOnce) {
  const std::string text =
      "parameters: {tip: {default: 1, unit: m}}\n" +
      cantilever("{E: 70000, nu: 0.3}", rod_section, "[0, -1e-6, 0, 0, 0, 0]", "[tip, 0, 0]");
  const ModelFamily family = parse_model_family(text, "swept.yaml");
  SweepOptions options;
  options.threads = 1;
  const SweepResult s = sweep(family, grid_poses({{"tip", 1, 2, 3}}), options);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_TRUE(contains(s.warnings[0], "links.L1.material.E: E = 70000 Pa is below"))
      << s.warnings[0];
  const auto summary = nlohmann::json::parse(sweep_summary_to_json(s, false, ""));
  ASSERT_EQ(summary["warnings"].size(), 1u);
  EXPECT_EQ(summary["warnings"][0], s.warnings[0]);
  // A load small enough for the linear range: the poses are ok and say nothing of deflections.
  for (const auto& pose : s.results) {
    EXPECT_EQ(pose.status, PoseStatus::ok);
    EXPECT_FALSE(pose.large_deflection);
  }
}

// ---- deflections beyond the linear method ---------------------------------------------------

// Tip rotation of a cantilever under a transverse tip force: θ = F·L²/(2·E·I).
std::string transverse_force_turning_by(double rotation) {
  const double force = rotation * 2 * youngs_modulus * second_moment / (length * length);
  return "[0, " + number(-force) + ", 0, 0, 0, 0]";
}

TEST(Plausibility, ATipTurningBeyondTheLinearRangeIsWarnedJustAboveTheThresholdOnly) {
  const double threshold = detail::kLargestLinearRotation;
  const Result above = solve(parse_model(
      cantilever(steel, rod_section, transverse_force_turning_by(1.2 * threshold)), "r.yaml"));
  EXPECT_NEAR(above.end_effectors[0].deflection->tail<3>().norm(), 1.2 * threshold,
              kTolerance * threshold);
  EXPECT_TRUE(contains(above.report.large_deflection,
                       "link end 'L1.to' turns 0.06 rad (more than 0.05 rad)"))
      << above.report.large_deflection;
  // The tip moves 2/3 of θ·L = 0.04 m, above 3 % of the rod's 1 m too.
  EXPECT_TRUE(contains(above.report.large_deflection,
                       "link end 'L1.to' moves 0.04 m (more than 3 % of the model's size, 1 m)"))
      << above.report.large_deflection;
  EXPECT_TRUE(any_contains(above.report.warnings, above.report.large_deflection));

  // θ = 0.04 rad moves the tip 0.0267 m: below both thresholds.
  const Result below = solve(parse_model(
      cantilever(steel, rod_section, transverse_force_turning_by(0.8 * threshold)), "r.yaml"));
  EXPECT_TRUE(below.report.large_deflection.empty()) << below.report.large_deflection;
  EXPECT_TRUE(plausibility_warnings(below).empty());
}

// A sweep's row takes only part of a solve's result (no joint results, no names but the end
// effectors'); its warning of large deflections is the full solve's, naming the link end from
// the model.
TEST(Plausibility, ASweepPoseBeyondTheLinearRangeSaysWhatItsSolveSays) {
  const std::string text =
      "parameters: {tip: {default: 1, unit: m}}\n" +
      cantilever(steel, rod_section,
                 transverse_force_turning_by(1.2 * detail::kLargestLinearRotation), "[tip, 0, 0]");
  const ModelFamily family = parse_model_family(text, "swept.yaml");
  SweepOptions options;
  options.threads = 1;
  options.keep_matrices = true;
  const SweepResult s = sweep(family, grid_poses({{"tip", 1, 1, 1}}), options);
  const Result solved = solve(family.build(family.default_values()));
  ASSERT_EQ(s.results.size(), 1u);
  const PoseResult& pose = s.results[0];
  ASSERT_EQ(pose.status, PoseStatus::ok) << pose.message;
  EXPECT_TRUE(pose.large_deflection);
  EXPECT_EQ(pose.message, solved.report.large_deflection);
  EXPECT_TRUE(contains(pose.message, "link end 'L1.to' turns 0.06 rad")) << pose.message;
  EXPECT_EQ(*pose.end_effectors[0].compliance, *solved.end_effectors[0].compliance);
  EXPECT_EQ(*pose.end_effectors[0].stiffness, *solved.end_effectors[0].stiffness);
}

// Tip displacement of a bar under an axial force: δ = F·L/(E·A), without rotation.
TEST(Plausibility, ATipMovingBeyondAFewPercentOfTheModelIsWarnedWithoutARotation) {
  const double fraction = detail::kLargestLinearTranslationFraction;
  const auto axial = [&](double stretch) {
    return "[" + number(stretch * youngs_modulus * area / length) + ", 0, 0, 0, 0, 0]";
  };
  const Result above =
      solve(parse_model(cantilever(steel, rod_section, axial(1.1 * fraction * length)), "a.yaml"));
  EXPECT_NEAR(above.end_effectors[0].deflection->x(), 1.1 * fraction * length,
              kTolerance * fraction);
  EXPECT_TRUE(contains(above.report.large_deflection, "link end 'L1.to' moves 0.033 m"))
      << above.report.large_deflection;
  EXPECT_FALSE(contains(above.report.large_deflection, "turns"));
  const Result below =
      solve(parse_model(cantilever(steel, rod_section, axial(0.9 * fraction * length)), "a.yaml"));
  EXPECT_TRUE(below.report.large_deflection.empty()) << below.report.large_deflection;
}

ModelFamily three_rpr(const ParameterSettings& settings = {}) {
  return load_model_family(
      std::string(STIFFMSA_SOURCE_DIR) + "/examples/planar-3rpr-parametric.yaml", {}, settings);
}

TEST(Plausibility, TheThreeRprNearItsSingularityIsWarned) {
  const ModelFamily family = three_rpr({{"x", 0.32}, {"y", 0.7605}});
  const Result result = solve(family.build(family.default_values()));
  EXPECT_GT(result.end_effectors[0].deflection->tail<3>().norm(), 1.0);
  EXPECT_TRUE(contains(result.report.large_deflection, "link end 'platform_1.from' turns"))
      << result.report.large_deflection;
  EXPECT_TRUE(contains(result.report.large_deflection, "near a singularity"));
}

TEST(Plausibility, ASweepKeepsTheNumbersOfALargeDeflectionPoseAndCountsIt) {
  const ModelFamily family = three_rpr();
  PoseTable poses;
  poses.parameters = {"x", "y"};
  poses.values = {0.32, 0.7605, 0.3, 0.6};
  SweepOptions options;
  options.threads = 1;
  const SweepResult s = sweep(family, poses, options);
  ASSERT_EQ(s.results.size(), 2u);
  EXPECT_EQ(s.results[0].status, PoseStatus::ok);
  EXPECT_TRUE(s.results[0].large_deflection);
  EXPECT_TRUE(contains(s.results[0].message, "too large for the linear method"))
      << s.results[0].message;
  ASSERT_EQ(s.results[0].end_effectors.size(), 1u);
  EXPECT_GT(s.results[0].end_effectors[0].deflection_rotation, 1.0);
  EXPECT_FALSE(s.results[1].large_deflection);
  EXPECT_TRUE(s.results[1].message.empty()) << s.results[1].message;

  const auto summary = nlohmann::json::parse(sweep_summary_to_json(s, false, "m.csv"));
  EXPECT_EQ(summary["large_deflection"], 1);
  EXPECT_EQ(summary["status"]["ok"], 2);
  EXPECT_TRUE(summary["warnings"].empty());
}

// ---- principal directions, stiffness along a direction, condition ---------------------------

// A compliance whose translational block is R·diag(c)·Rᵀ and rotational block diag(r).
Mat6 rotated_compliance(const Mat3& rotation, const Vec3& c, const Vec3& r) {
  Mat6 compliance = Mat6::Zero();
  compliance.topLeftCorner<3, 3>() = rotation * c.asDiagonal() * rotation.transpose();
  compliance.bottomRightCorner<3, 3>() = r.asDiagonal();
  return compliance;
}

TEST(PrincipalStiffness, DirectionsAreTheEigenvectorsInTheOrderOfTheValues) {
  const Mat3 rotation = Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Vec3 c(1e-6, 4e-6, 2e-6);  // stiffness 1e6, 2.5e5, 5e5
  const PrincipalStiffness p =
      principal_stiffness(rotated_compliance(rotation, c, Vec3(1e-3, 1e-3, 0)));
  EXPECT_NEAR(p.translational(0), 2.5e5, kTolerance * 2.5e5);
  EXPECT_NEAR(p.translational(1), 5e5, kTolerance * 5e5);
  EXPECT_NEAR(p.translational(2), 1e6, kTolerance * 1e6);
  // Softest along the rotation's second axis, stiffest along its first.
  for (const auto& [value, axis] : {std::pair{0, 1}, std::pair{1, 2}, std::pair{2, 0}}) {
    const Vec3 direction = p.translational_directions.col(value);
    EXPECT_NEAR(direction.norm(), 1, kTolerance);
    EXPECT_NEAR(std::abs(direction.dot(rotation.col(axis))), 1, kTolerance) << value;
    Eigen::Index largest = 0;
    direction.cwiseAbs().maxCoeff(&largest);
    EXPECT_GT(direction(largest), 0);  // signed so that the largest component is positive
  }
  // A rotation held rigidly about z: unbounded, and last.
  EXPECT_EQ(p.rotational(2), std::numeric_limits<double>::infinity());
  EXPECT_NEAR(std::abs(p.rotational_directions(2, 2)), 1, kTolerance);
  EXPECT_NEAR(p.translational_condition(), 4, kTolerance);
}

TEST(PrincipalStiffness, StiffnessAlongADirectionIsTheInverseOfItsCompliance) {
  const Mat3 rotation = Eigen::AngleAxisd(0.7, Vec3(0, 1, 1).normalized()).toRotationMatrix();
  const Mat6 compliance = rotated_compliance(rotation, Vec3(1e-6, 4e-6, 2e-6), Vec3(1e-3, 2e-3, 0));
  const Vec3 u(1, 2, 2);  // length 3
  const DirectionalStiffness along = directional_stiffness(compliance, u);
  const Vec3 unit = u / 3;
  EXPECT_NEAR((along.direction - unit).norm(), 0, kTolerance);
  const double expected = 1 / unit.dot(compliance.topLeftCorner<3, 3>() * unit);
  EXPECT_NEAR(along.translational, expected, kTolerance * expected);
  EXPECT_NEAR(along.rotational, 1 / (unit(0) * unit(0) * 1e-3 + unit(1) * unit(1) * 2e-3),
              kTolerance * 1e3);
  // Along a principal direction, the principal value.
  EXPECT_NEAR(directional_stiffness(compliance, rotation.col(1)).translational, 2.5e5,
              kTolerance * 2.5e5);
  // About z the rotation is held rigidly.
  EXPECT_EQ(directional_stiffness(compliance, Vec3(0, 0, 5)).rotational,
            std::numeric_limits<double>::infinity());
  EXPECT_THROW(directional_stiffness(compliance, Vec3::Zero()), UsageError);
}

TEST(PrincipalStiffness, ASolveWithADirectionReportsItAndTheResultFileHoldsItAll) {
  // The cantilever: against a transverse force along y, k = 3·E·I / L³.
  SolveOptions options;
  options.direction = Vec3(0, 2, 0);
  const Result result = solve(
      parse_model(cantilever(steel, rod_section, "[0, -100, 0, 0, 0, 0]"), "c.yaml"), options);
  const auto& along = result.end_effectors[0].along_direction;
  ASSERT_TRUE(along);
  const double bending = 3 * youngs_modulus * second_moment / std::pow(length, 3);
  EXPECT_NEAR(along->translational, bending, kTolerance * bending);

  const auto json = nlohmann::json::parse(result_to_json(result));
  const auto& ee = json["end_effectors"]["EE"];
  EXPECT_EQ(ee["along_direction"]["direction"], (std::vector<double>{0, 1, 0}));
  EXPECT_NEAR(ee["along_direction"]["translational"].get<double>(), bending, kTolerance * bending);
  const auto& translational = ee["principal_stiffness"]["translational"];
  ASSERT_EQ(translational["values"].size(), 3u);
  EXPECT_NEAR(translational["values"][0].get<double>(), bending, kTolerance * bending);
  ASSERT_EQ(translational["directions"].size(), 3u);
  // The two bending directions tie; the stiffest is the rod's axis.
  EXPECT_NEAR(translational["directions"][2][0].get<double>(), 1, kTolerance);
  EXPECT_TRUE(json["parameters"].empty());

  SolveOptions bad;
  bad.direction = Vec3(0, std::nan(""), 0);
  EXPECT_THROW(bad.validate(), UsageError);
}

TEST(PrincipalStiffness, ASweepWritesTheConditionAndTheDirectionalColumns) {
  const ModelFamily family = three_rpr();
  SweepOptions options;
  options.threads = 1;
  options.solve.direction = Vec3(3, 4, 0);
  const SweepResult s = sweep(family, grid_poses({{"x", 0.4, 0.5, 3}}), options);
  ASSERT_TRUE(s.direction);
  EXPECT_NEAR((*s.direction - Vec3(0.6, 0.8, 0)).norm(), 0, kTolerance);
  const auto cond = find_sweep_column(s, "platform.cond_trans");
  const auto along = find_sweep_column(s, "platform.k_trans_dir");
  ASSERT_TRUE(cond && along);
  for (std::size_t pose = 0; pose < 3; ++pose) {
    const auto& m = s.results[pose].end_effectors[0];
    EXPECT_EQ(column_value(s, *cond, pose),
              m.principal.translational(2) / m.principal.translational(0));
    std::vector<double> values = family.default_values();
    values[*family.find_parameter("x")] = s.poses.pose(pose)[0];
    const Result alone = solve(family.build(values), options.solve);
    EXPECT_EQ(column_value(s, *along, pose), alone.end_effectors[0].along_direction->translational);
    EXPECT_GE(column_value(s, *along, pose), m.principal.translational(0) * (1 - kTolerance));
    EXPECT_LE(column_value(s, *along, pose), m.principal.translational(2) * (1 + kTolerance));
  }
  EXPECT_TRUE(contains(sweep_to_csv(s, false),
                       ",platform.cond_trans,platform.k_trans_dir,platform.k_rot_dir\n"));
  const auto summary = nlohmann::json::parse(sweep_summary_to_json(s, false, ""));
  EXPECT_NEAR(summary["direction"][1].get<double>(), 0.8, kTolerance);
  // Without a direction, no directional columns.
  options.solve.direction.reset();
  EXPECT_FALSE(find_sweep_column(sweep(family, grid_poses({{"x", 0.3, 0.4, 2}}), options),
                                 "platform.k_trans_dir"));
}

// ---- what a result records of its parameters --------------------------------------------------

TEST(RecordedParameters, SettingsAndDefaultsAreTold) {
  const ModelFamily family = three_rpr({{"y", 0.65}});
  const auto values = family.parameter_values();
  ASSERT_EQ(values.size(), family.parameters().size());
  for (const auto& v : values) {
    EXPECT_EQ(v.set, v.name == "y") << v.name;
    if (v.name == "y") EXPECT_EQ(v.value, 0.65);
  }
  // A model built from the family, or loaded at the file's defaults, carries its values.
  std::vector<double> moved = family.default_values();
  moved[0] = 0.41;
  const Model member = family.build(moved);
  ASSERT_EQ(member.parameters.size(), values.size());
  EXPECT_EQ(member.parameters[0].name, "x");
  EXPECT_EQ(member.parameters[0].value, 0.41);
  EXPECT_EQ(member.parameters[1].value, 0.65);
  EXPECT_TRUE(member.parameters[1].set);
  const Model loaded =
      load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/planar-3rpr-parametric.yaml");
  ASSERT_EQ(loaded.parameters.size(), values.size());
  EXPECT_EQ(loaded.parameters[1].value, 0.33);
  EXPECT_FALSE(loaded.parameters[1].set);
  EXPECT_TRUE(load_model(std::string(STIFFMSA_SOURCE_DIR) + "/examples/cantilever.yaml")
                  .parameters.empty());

  Result result = solve(family.build(family.default_values()));
  result.parameters = values;
  const auto json = nlohmann::json::parse(result_to_json(result));
  EXPECT_EQ(json["parameters"]["y"]["value"], 0.65);
  EXPECT_EQ(json["parameters"]["y"]["unit"], "m");
  EXPECT_EQ(json["parameters"]["y"]["set"], true);
  EXPECT_EQ(json["parameters"]["x"]["set"], false);

  PoseTable poses;
  poses.parameters = {"x"};
  poses.values = {0.3};
  SweepOptions options;
  options.threads = 1;
  const SweepResult s = sweep(family, poses, options);
  const auto summary = nlohmann::json::parse(sweep_summary_to_json(s, false, ""));
  EXPECT_FALSE(summary["fixed_parameters"].contains("x"));
  EXPECT_EQ(summary["fixed_parameters"]["y"]["value"], 0.65);
  EXPECT_EQ(summary["fixed_parameters"]["y"]["set"], true);
  EXPECT_EQ(summary["fixed_parameters"]["r"]["set"], false);
  // with_defaults() records what it changed.
  std::vector<double> changed = family.default_values();
  changed[0] += 0.01;
  EXPECT_TRUE(family.with_defaults(changed).parameter_values()[0].set);
}

// ---- numbers for people and files ---------------------------------------------------------------

TEST(NumberText, ShortestTextReadsBackAndHasNoNegativeZero) {
  EXPECT_EQ(shortest_text(0.1), "0.1");
  EXPECT_EQ(shortest_text(70000), "70000");
  EXPECT_EQ(shortest_text(2.1e11), "2.1e+11");
  EXPECT_EQ(shortest_text(-0.0), "0");
  EXPECT_EQ(shortest_text(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(shortest_text(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(shortest_text(0.1 + 0.2), "0.30000000000000004");  // another double than 0.3
  EXPECT_EQ(counted(1, "thread"), "1 thread");
  EXPECT_EQ(counted(0, "pose"), "0 poses");
  EXPECT_EQ(counted(2, "number"), "2 numbers");
}

TEST(NumberText, GridValuesAreTheDecimalsTheGridWasWrittenIn) {
  const GridAxis axis{"x", 0, 1, 101};
  EXPECT_EQ(axis.value(11), 0.11);  // the interpolation alone gives 0.11000000000000001
  EXPECT_EQ(shortest_text(axis.value(11)), "0.11");
  EXPECT_EQ(axis.value(29), 0.29);
  // Where no shorter decimal is within rounding, the interpolated value stays.
  const GridAxis thirds{"x", 0, 1, 4};
  EXPECT_EQ(thirds.value(1), 1.0 / 3.0);
  const GridAxis negative{"x", -0.2, 0.2, 41};
  EXPECT_EQ(negative.value(13), -0.07);
  EXPECT_EQ(shortest_text(negative.value(20)), "0");
  const PoseTable table = grid_poses({{"x", 0.1, 0.2, 11}});
  EXPECT_EQ(table.pose(1)[0], 0.11);
}

TEST(NumberText, MessagesCountInTheRightNumber) {
  // A revolute joint's preload is one number.
  const std::string model = R"(format: stiffmsa/1
points: {O: [0, 0, 0], A: [1, 0, 0]}
links:
  a: {type: rigid, from: O, to: A}
supports:
  S: {type: revolute, axis: [0, 0, 1], at: O, stiffness: [[1e4]], preload: [1, 2]}
)";
  try {
    parse_model(model, "p.yaml");
    FAIL() << "the preload's length is a defect";
  } catch (const InputError& e) {
    ASSERT_FALSE(e.diagnostics().empty());
    EXPECT_TRUE(contains(e.diagnostics()[0].message, "expected 1 number "))
        << e.diagnostics()[0].message;
  }
  try {
    parse_pose_table("x\n0.1, 0.2\n", "poses.csv");
    FAIL() << "two values under one name is a defect";
  } catch (const InputError& e) {
    ASSERT_FALSE(e.diagnostics().empty());
    EXPECT_EQ(e.diagnostics()[0].message,
              "expected 1 value (one per parameter of the header), got 2");
  }
  try {
    three_rpr().build(std::vector<double>{0.3});
    FAIL() << "one value for five parameters is a usage error";
  } catch (const UsageError& e) {
    EXPECT_TRUE(contains(e.what(), "has 5 parameters; got 1 value")) << e.what();
  }
}

}  // namespace
