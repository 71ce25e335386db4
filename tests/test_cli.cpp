// End to end: the stiffmsa program as a user runs it, its exit codes, messages and result file.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>

#include "builders.hpp"
#include "command_line.hpp"

namespace {

namespace fs = std::filesystem;
using stiffmsa::testing::contains;
using stiffmsa::testing::read_file;
using stiffmsa::testing::shell_quoted;

constexpr int exit_success = 0;
constexpr int exit_cannot_solve = 1;
constexpr int exit_invalid_input = 2;

constexpr const char* error_prefix = "stiffmsa: error: ";

// A steel rod of 1 m clamped at O, loaded at its tip E.
constexpr double length = 1.0;
constexpr double youngs_modulus = 2.1e11;
constexpr double diameter = 0.05;
constexpr const char* cantilever_model = stiffmsa::testing::kCantileverYaml;

// The same rod with its support naming a point that does not exist.
constexpr const char* invalid_model = R"(format: stiffmsa/1
name: broken
points:
  O: [0, 0, 0]
  E: [1, 0, 0]
links:
  L1:
    type: beam
    from: O
    to: E
    material: {E: 2.1e11, nu: 0.3}
    section: {shape: circle, D: 0.05}
supports:
  S1: {type: rigid, at: Nowhere, link: L1}
end_effectors:
  EE: {at: E, link: L1}
)";

// Valid, but nothing holds the rod against its load: a mechanism.
constexpr const char* unsupported_model = R"(format: stiffmsa/1
name: floating
points:
  O: [0, 0, 0]
  E: [1, 0, 0]
links:
  L1:
    type: beam
    from: O
    to: E
    material: {E: 2.1e11, nu: 0.3}
    section: {shape: circle, D: 0.05}
loads:
  - {at: E, link: L1, wrench: [0, -100, 0, 0, 0, 0]}
end_effectors:
  EE: {at: E, link: L1}
)";

struct CliRun {
  int exit_code = -1;
  std::string out;
  std::string err;
};

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    folder_ = fs::temp_directory_path() /
              ("stiffmsa-test-cli-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  fs::path write_model(const std::string& file_name, const std::string& text) const {
    const fs::path path = folder_ / file_name;
    std::ofstream(path) << text;
    return path;
  }

  // Runs the program with `arguments` (already quoted where needed), no stdin.
  CliRun run(const std::string& arguments) const {
    const fs::path out = folder_ / "stdout.txt";
    const fs::path err = folder_ / "stderr.txt";
    const std::string command = shell_quoted(STIFFMSA_CLI) + " " + arguments + " >" +
                                shell_quoted(out.string()) + " 2>" + shell_quoted(err.string()) +
                                " </dev/null";
    const int status = std::system(command.c_str());
    CliRun result;
    if (status != -1 && WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
    result.out = read_file(out);
    result.err = read_file(err);
    return result;
  }

  fs::path folder_;
};

TEST_F(Cli, Version) {
  const CliRun r = run("--version");
  EXPECT_EQ(r.exit_code, exit_success) << r.err;
  EXPECT_TRUE(contains(r.out, "stiffmsa")) << r.out;
}

TEST_F(Cli, HelpIsNotAnError) {
  const CliRun r = run("--help");
  EXPECT_EQ(r.exit_code, exit_success) << r.err;
  EXPECT_TRUE(contains(r.out, "solve")) << r.out;
  EXPECT_TRUE(contains(r.out, "check")) << r.out;
}

TEST_F(Cli, MissingModelFileIsInvalidInput) {
  const fs::path missing = folder_ / "no-such-model.yaml";
  const CliRun r = run("solve " + shell_quoted(missing.string()));
  EXPECT_EQ(r.exit_code, exit_invalid_input);
  EXPECT_TRUE(contains(r.err, error_prefix)) << r.err;
  EXPECT_TRUE(contains(r.err, "no-such-model.yaml")) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST_F(Cli, BadOptionIsInvalidInput) {
  const fs::path model = write_model("cantilever.yaml", cantilever_model);
  const fs::path json = folder_ / "result.json";
  const CliRun r = run("solve " + shell_quoted(model.string()) + " --no-such-option --json " +
                       shell_quoted(json.string()));
  EXPECT_EQ(r.exit_code, exit_invalid_input);
  EXPECT_TRUE(contains(r.err, error_prefix)) << r.err;
  EXPECT_TRUE(contains(r.err, "--no-such-option")) << r.err;
  EXPECT_FALSE(fs::exists(json));
}

TEST_F(Cli, UnknownSolverIsInvalidInput) {
  const fs::path model = write_model("cantilever.yaml", cantilever_model);
  const CliRun r = run("solve " + shell_quoted(model.string()) + " --solver cholesky");
  EXPECT_EQ(r.exit_code, exit_invalid_input);
  EXPECT_TRUE(contains(r.err, error_prefix)) << r.err;
}

TEST_F(Cli, MissingSubcommandIsInvalidInput) {
  const CliRun r = run("");
  EXPECT_EQ(r.exit_code, exit_invalid_input);
  EXPECT_TRUE(contains(r.err, error_prefix)) << r.err;
}

TEST_F(Cli, InvalidModelIsInvalidInputAndWritesNoResult) {
  const fs::path model = write_model("broken.yaml", invalid_model);
  const fs::path json = folder_ / "result.json";
  const CliRun r =
      run("solve " + shell_quoted(model.string()) + " --json " + shell_quoted(json.string()));
  EXPECT_EQ(r.exit_code, exit_invalid_input);
  EXPECT_TRUE(contains(r.err, error_prefix)) << r.err;
  EXPECT_TRUE(contains(r.err, "Nowhere")) << r.err;
  EXPECT_FALSE(fs::exists(json));
}

TEST_F(Cli, FailedRunLeavesAnEarlierResultFileAlone) {
  const fs::path model = write_model("broken.yaml", invalid_model);
  const fs::path json = folder_ / "result.json";
  std::ofstream(json) << "earlier result";
  const CliRun r =
      run("solve " + shell_quoted(model.string()) + " --json " + shell_quoted(json.string()));
  EXPECT_EQ(r.exit_code, exit_invalid_input);
  EXPECT_EQ(read_file(json), "earlier result");
}

TEST_F(Cli, CheckRejectsAnInvalidModel) {
  const fs::path model = write_model("broken.yaml", invalid_model);
  const CliRun r = run("check " + shell_quoted(model.string()));
  EXPECT_EQ(r.exit_code, exit_invalid_input);
  EXPECT_TRUE(contains(r.err, error_prefix)) << r.err;
}

TEST_F(Cli, MechanismCannotBeSolved) {
  const fs::path model = write_model("floating.yaml", unsupported_model);
  const fs::path json = folder_ / "result.json";
  const CliRun r =
      run("solve " + shell_quoted(model.string()) + " --json " + shell_quoted(json.string()));
  EXPECT_EQ(r.exit_code, exit_cannot_solve) << r.out << r.err;
  EXPECT_TRUE(contains(r.err, error_prefix)) << r.err;
  EXPECT_FALSE(fs::exists(json));
}

TEST_F(Cli, MechanismMessageIsASentenceThenItsCausesOnce) {
  const fs::path model = write_model("floating.yaml", unsupported_model);
  const CliRun r = run("solve " + shell_quoted(model.string()));
  EXPECT_EQ(r.exit_code, exit_cannot_solve) << r.out << r.err;
  EXPECT_EQ(
      r.err,
      std::string(error_prefix) +
          "the model is a mechanism with 6 free motions and carries loads or preloads, which a "
          "mechanism cannot hold (only an unloaded one is solved)\n"
          "  the model has no support: nothing holds it, so it can move as a whole; add one under "
          "`supports:`\n");
}

// A planar 3R arm of rigid links; its three elastic revolute axes are along z at O, A and B.
constexpr const char* planar_3r_model = R"(format: stiffmsa/1
name: planar-3r
points:
  O: [0, 0, 0]
  A: [0.4, 0.1, 0]
  B: [0.7, 0.35, 0]
  E: [0.8, 0.6, 0]
links:
  l1: {type: rigid, from: O, to: A}
  l2: {type: rigid, from: A, to: B}
  l3: {type: rigid, from: B, to: E}
joints:
  j2: {type: revolute, at: A, links: [l1, l2], axis: [0, 0, 1], stiffness: 2.0e4}
  j3: {type: revolute, at: B, links: [l2, l3], axis: [0, 0, 1], stiffness: 1.0e4}
supports:
  j1: {type: revolute, at: O, axis: [0, 0, 1], stiffness: 3.0e4}
end_effectors:
  tip: {at: E}
)";

TEST_F(Cli, RigidPlanarArmGetsItsInPlaneStiffness) {
  // K_plane = J⁻ᵀ·diag(k)·J⁻¹ on x, y, rz, J's columns [−(E − P_i)_y, (E − P_i)_x, 1] (z × (E −
  // P_i), 1).
  const fs::path model = write_model("planar-3r.yaml", planar_3r_model);
  const fs::path json = folder_ / "result.json";
  const CliRun r =
      run("solve " + shell_quoted(model.string()) + " --json " + shell_quoted(json.string()));
  ASSERT_EQ(r.exit_code, exit_success) << r.err;
  EXPECT_TRUE(
      contains(r.out,
               "  Stiffness: unbounded (the end effector is held rigidly in some direction)\n"
               "  Stiffness on the 3 directions not held rigidly (reduced_stiffness)\n"))
      << r.out;
  EXPECT_TRUE(contains(r.out, "                dx           dy           rz\n    Fx")) << r.out;

  const nlohmann::json result = nlohmann::json::parse(read_file(json));
  const auto& tip = result["end_effectors"]["tip"];
  EXPECT_TRUE(tip["stiffness"].is_null());
  const nlohmann::json axes = {{1.0, 0.0, 0.0, 0.0, 0.0, 0.0},
                               {0.0, 1.0, 0.0, 0.0, 0.0, 0.0},
                               {0.0, 0.0, 0.0, 0.0, 0.0, 1.0}};
  EXPECT_EQ(tip["reduced_stiffness"]["directions"], axes);
  const double points[3][2] = {{0, 0}, {0.4, 0.1}, {0.7, 0.35}}, k[3] = {3.0e4, 2.0e4, 1.0e4};
  double J[3][3];
  for (int i = 0; i < 3; ++i) {
    J[0][i] = -(0.6 - points[i][1]);
    J[1][i] = 0.8 - points[i][0];
    J[2][i] = 1;
  }
  // J⁻¹ by cofactors, then K = J⁻ᵀ·diag(k)·J⁻¹.
  double inverse[3][3];
  const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
                     J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                     J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
      inverse[i][j] = (J[r0][c0] * J[r1][c1] - J[r0][c1] * J[r1][c0]) / det;
    }
  double largest = 0, worst = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      double expected = 0;
      for (int i = 0; i < 3; ++i) expected += inverse[i][a] * k[i] * inverse[i][b];
      largest = std::max(largest, std::abs(expected));
      worst = std::max(worst,
                       std::abs(tip["reduced_stiffness"]["matrix"][a][b].get<double>() - expected));
    }
  EXPECT_LT(worst / largest, 1e-9);
}

TEST_F(Cli, CheckPrintsTheSystemSize) {
  const fs::path model = write_model("cantilever.yaml", cantilever_model);
  const CliRun r = run("check " + shell_quoted(model.string()));
  ASSERT_EQ(r.exit_code, exit_success) << r.err;
  // One link: two link ends of 12 unknowns each (deflection and wrench).
  EXPECT_TRUE(contains(r.out, "24 unknowns")) << r.out;
}

TEST_F(Cli, SolvesTheCantileverAndWritesTheResultFile) {
  const fs::path model = write_model("cantilever.yaml", cantilever_model);
  const fs::path json = folder_ / "result.json";
  const CliRun r =
      run("solve " + shell_quoted(model.string()) + " --json " + shell_quoted(json.string()));
  ASSERT_EQ(r.exit_code, exit_success) << r.err;
  EXPECT_TRUE(contains(r.out, "cantilever")) << r.out;
  EXPECT_TRUE(contains(r.out, "EE")) << r.out;

  ASSERT_TRUE(fs::exists(json));
  const auto result = nlohmann::json::parse(read_file(json));
  EXPECT_EQ(result["format"], "stiffmsa-result/1");
  EXPECT_EQ(result["model"], "cantilever");
  EXPECT_EQ(result["system"]["unknowns"], 24);
  for (const char* key : {"end_effectors", "link_ends", "joints", "supports"}) {
    EXPECT_TRUE(result.contains(key)) << key;
  }

  // Euler–Bernoulli: the tip of a clamped beam moves L³/(3·E·Iz) per unit force along y.
  const double second_moment_z = std::numbers::pi * std::pow(diameter, 4) / 64.0;
  const double expected = std::pow(length, 3) / (3.0 * youngs_modulus * second_moment_z);
  const auto& compliance = result["end_effectors"]["EE"]["compliance"];
  ASSERT_TRUE(compliance.is_array()) << compliance;
  const double computed = compliance[1][1].get<double>();
  EXPECT_NEAR(computed, expected, 1e-9 * expected);

  // The load is −100 N along y.
  const auto& deflection = result["end_effectors"]["EE"]["deflection"];
  ASSERT_TRUE(deflection.is_array()) << deflection;
  EXPECT_NEAR(deflection[1].get<double>(), -100.0 * expected, 1e-9 * 100.0 * expected);

  const auto& reaction = result["supports"]["S1"]["reaction"];
  ASSERT_TRUE(reaction.is_array()) << reaction;
  EXPECT_NEAR(reaction[1].get<double>(), 100.0, 1e-6);
}

TEST_F(Cli, SolveWithoutJsonWritesNoFile) {
  const fs::path model = write_model("cantilever.yaml", cantilever_model);
  const CliRun r = run("solve " + shell_quoted(model.string()));
  ASSERT_EQ(r.exit_code, exit_success) << r.err;
  EXPECT_TRUE(contains(r.out, "unknowns")) << r.out;
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder_)) ++files;
  EXPECT_EQ(files, 3u);  // the model, stdout.txt and stderr.txt
}

TEST_F(Cli, RefusesToWriteTheResultOverTheModel) {
  const fs::path model = write_model("cantilever.yaml", cantilever_model);
  const CliRun r =
      run("solve " + shell_quoted(model.string()) + " --json " + shell_quoted(model.string()));
  EXPECT_EQ(r.exit_code, exit_invalid_input);
  EXPECT_EQ(read_file(model), cantilever_model);
}

}  // namespace

namespace {

// A clamped arm braced by a strut with ball joints at both ends: the strut can spin about its
// own axis, a free motion that moves no end effector.
constexpr const char* braced_arm_model = R"(format: stiffmsa/1
name: braced-arm
materials:
  steel: {E: 2.1e11, G: 8.0e10}
points:
  O: [0, 0, 0.5]
  E: [0.8, 0, 0.5]
  G: [0.8, 0.6, 0]
links:
  arm: {type: beam, from: O, to: E, material: steel, section: {shape: circle, D: 0.04}}
  strut: {type: beam, from: G, to: E, material: steel, section: {shape: circle, D: 0.015}}
supports:
  clamp: {type: rigid, at: O}
  ball_ground: {type: spherical, at: G}
joints:
  ball_top: {type: spherical, at: E, links: [arm, strut]}
loads:
  - {at: E, link: arm, wrench: [0, 0, -300, 0, 0, 0]}
end_effectors:
  tip: {at: E, link: arm}
)";

}  // namespace

TEST_F(Cli, IdleMotionIsRefusedWithAHintThenAcceptedByFlagOrModelOption) {
  const fs::path model = write_model("braced.yaml", braced_arm_model);
  const fs::path json = folder_ / "result.json";
  const CliRun refused =
      run("solve " + shell_quoted(model.string()) + " --json " + shell_quoted(json.string()));
  EXPECT_EQ(refused.exit_code, exit_cannot_solve) << refused.out << refused.err;
  EXPECT_TRUE(contains(refused.err, "'strut'")) << refused.err;
  EXPECT_TRUE(contains(refused.err, "idle motion")) << refused.err;
  EXPECT_TRUE(contains(refused.err, "--accept-idle-motions")) << refused.err;
  EXPECT_FALSE(fs::exists(json));

  const CliRun accepted = run("solve " + shell_quoted(model.string()) +
                              " --accept-idle-motions --json " + shell_quoted(json.string()));
  ASSERT_EQ(accepted.exit_code, exit_success) << accepted.out << accepted.err;
  const auto result = nlohmann::json::parse(read_file(json));
  EXPECT_FALSE(result["end_effectors"]["tip"]["stiffness"].is_null());
  EXPECT_TRUE(result["link_ends"]["strut"]["to"]["deflection"].is_null());
  EXPECT_FALSE(result["link_ends"]["arm"]["to"]["deflection"].is_null());

  const fs::path with_option =
      write_model("braced-option.yaml",
                  std::string(braced_arm_model) + "options: {accept_idle_motions: true}\n");
  const CliRun by_option = run("solve " + shell_quoted(with_option.string()));
  EXPECT_EQ(by_option.exit_code, exit_success) << by_option.out << by_option.err;
}

namespace {

std::string example_path(const std::string& name) {
  return shell_quoted(std::string(STIFFMSA_SOURCE_DIR) + "/examples/" + name);
}

std::size_t line_count(const std::string& text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

}  // namespace

// A model with load cases gets its critical load factors unasked; --no-critical-load drops them
// from the summary and the result file and changes no other number; with --critical-load it is
// a usage error.
TEST_F(Cli, NoCriticalLoadDropsTheFactorGivenUnasked) {
  const std::string model =
      shell_quoted(std::string(STIFFMSA_SOURCE_DIR) + "/examples/portal-frame-load-cases.yaml");
  const fs::path usual = folder_ / "usual.json", without = folder_ / "without.json";
  const CliRun unasked = run("solve " + model + " --json " + shell_quoted(usual.string()));
  ASSERT_EQ(unasked.exit_code, exit_success) << unasked.err;
  EXPECT_TRUE(contains(unasked.out, "critical load factor")) << unasked.out;
  const CliRun never =
      run("solve " + model + " --no-critical-load --json " + shell_quoted(without.string()));
  ASSERT_EQ(never.exit_code, exit_success) << never.err;
  EXPECT_FALSE(contains(never.out, "ritical load factor")) << never.out;
  const auto without_factor_lines = [](const std::string& text) {
    std::istringstream in(text);
    std::string line, kept;
    while (std::getline(in, line))
      if (!contains(line, "\"critical_load_")) kept += line + '\n';
    return kept;
  };
  const std::string usual_text = read_file(usual), without_text = read_file(without);
  EXPECT_TRUE(contains(usual_text, "\"critical_load_factor\""));
  EXPECT_FALSE(contains(without_text, "\"critical_load_"));
  EXPECT_EQ(without_text, without_factor_lines(usual_text));
  const CliRun both = run("solve " + model + " --critical-load --no-critical-load");
  EXPECT_EQ(both.exit_code, exit_invalid_input);
  EXPECT_TRUE(contains(both.err, "excludes")) << both.err;
}

TEST_F(Cli, SweepWritesRowsSummaryAndMaps) {
  const fs::path csv = folder_ / "map.csv";
  const CliRun r = run("sweep " + example_path("planar-3rpr-parametric.yaml") +
                       " --grid x=0.3:0.6:4 --grid y=0.2:0.4:3 --set phi=0.1 --plot --csv " +
                       shell_quoted(csv.string()));
  ASSERT_EQ(r.exit_code, exit_success) << r.out << r.err;
  const std::string rows = read_file(csv);
  EXPECT_EQ(line_count(rows), 1u + 12u);
  EXPECT_TRUE(rows.starts_with("x,y,status,message,platform.k_trans_min,")) << rows.substr(0, 200);
  const auto summary = nlohmann::json::parse(read_file(folder_ / "map.summary.json"));
  EXPECT_EQ(summary["poses"], 12);
  EXPECT_EQ(summary["status"]["ok"], 12);
  for (const char* plot :
       {"map.platform.k_trans_min.png", "map.platform.k_trans_min.svg",
        "map.platform.deflection_trans.png", "map.platform.deflection_trans.svg"})
    EXPECT_GT(fs::file_size(folder_ / plot), 1000u) << plot;
  EXPECT_TRUE(contains(r.out, "12 poses over x, y")) << r.out;
  EXPECT_TRUE(contains(r.out, "smallest platform.k_trans_min")) << r.out;
  EXPECT_TRUE(r.err.empty()) << r.err;  // no progress bar when stderr is not a terminal
}

TEST_F(Cli, SweepSetChangesTheUnsweptParameters) {
  const fs::path a = folder_ / "a.csv", b = folder_ / "b.csv";
  ASSERT_EQ(run("sweep " + example_path("planar-3rpr-parametric.yaml") +
                " --grid x=0.4:0.5:2 --csv " + shell_quoted(a.string()))
                .exit_code,
            exit_success);
  ASSERT_EQ(run("sweep " + example_path("planar-3rpr-parametric.yaml") +
                " --grid x=0.4:0.5:2 --set k_actuator=3e7 --csv " + shell_quoted(b.string()))
                .exit_code,
            exit_success);
  EXPECT_NE(read_file(a), read_file(b));
}

TEST_F(Cli, SweepOverAPoseFileWithFullMatrices) {
  const fs::path poses = write_model("poses.csv", "px,py\n0.3,0.25\n0.7,0.25\n");
  const fs::path csv = folder_ / "rows.csv";
  const CliRun r =
      run("sweep " + example_path("tripteron-parametric.yaml") + " --poses " +
          shell_quoted(poses.string()) + " --full --threads 1 --csv " + shell_quoted(csv.string()));
  ASSERT_EQ(r.exit_code, exit_success) << r.err;
  const std::string rows = read_file(csv);
  EXPECT_TRUE(contains(rows, ",platform.C11,")) << rows.substr(0, 300);
  EXPECT_TRUE(contains(rows, ",platform.K66\n")) << rows.substr(0, 900);
  EXPECT_TRUE(contains(rows, "\n0.7,0.25,invalid,\""))
      << rows;  // out of reach, and the sweep went on
  EXPECT_TRUE(contains(r.out, "invalid 1")) << r.out;
}

TEST_F(Cli, SweepUsageErrorsNameTheOption) {
  const fs::path csv = folder_ / "x.csv";
  const std::string model = example_path("planar-3rpr-parametric.yaml");
  const std::string out = " --csv " + shell_quoted(csv.string());
  struct Case {
    std::string arguments, expected;
  };
  for (const Case& c : std::vector<Case>{
           {" --grid x=0.1:0.2", "three values"},
           {" --grid x=0.1:0.2:0", "at least 1"},
           {" --grid =0.1:0.2:3", "no parameter name"},
           {" --grid xx=0.1:0.2:3", "did you mean 'x'"},
           {"", "either as --grid"},
           {" --grid x=0:1:2 --grid y=0:1:2 --grid phi=0:1:2 --plot", "2-D grid"},
           {" --grid x=0:1:2 --set q=1", "no parameter 'q'"},
           {" --grid x=0:1:2 --set x", "NAME=VALUE"},
       }) {
    const CliRun r = run("sweep " + model + c.arguments + out);
    EXPECT_EQ(r.exit_code, exit_invalid_input) << c.arguments;
    EXPECT_TRUE(contains(r.err, c.expected)) << c.arguments << ": " << r.err;
    EXPECT_FALSE(fs::exists(csv)) << c.arguments;
  }
}

TEST_F(Cli, SweepRefusesToWriteOverItsInputsBeforeSolving) {
  const fs::path model =
      write_model("truss.yaml", std::string("format: stiffmsa/1\nparameters: {h: 0.5}\n") +
                                    "points: {a: [0, 0, 0], b: [1, h, 0]}\n"
                                    "links: {l: {type: rigid, from: a, to: b}}\n"
                                    "supports: {s: {type: rigid, at: a}}\n"
                                    "end_effectors: {e: {at: b}}\n");
  const std::string before = read_file(model);
  const fs::path poses = write_model("poses.csv", "h\n0.1\n");
  const fs::path csv = folder_ / "rows.csv";
  struct Case {
    std::string arguments, expected;
  };
  for (const Case& c : std::vector<Case>{
           {"--grid h=0:1:2 --csv " + shell_quoted(model.string()), "is the model file"},
           {"--poses " + shell_quoted(poses.string()) + " --csv " + shell_quoted(poses.string()),
            "is the pose file"},
           {"--grid h=0:1:2 --csv " + shell_quoted(csv.string()) + " --summary " +
                shell_quoted(csv.string()),
            "would replace the CSV"},
           {"--grid h=0:1:2 --csv " + shell_quoted((folder_ / "no-such-folder" / "x.csv").string()),
            "does not exist"},
           {"--grid h=1:0:3 --plot --csv " + shell_quoted(csv.string()), "must run upwards"},
           {"--grid h=0:1:3 --plot --plot-column e.k_nothing --csv " + shell_quoted(csv.string()),
            "no such column"},
       }) {
    const CliRun r = run("sweep " + shell_quoted(model.string()) + " " + c.arguments);
    EXPECT_EQ(r.exit_code, exit_invalid_input) << c.arguments << r.out;
    EXPECT_TRUE(contains(r.err, c.expected)) << c.arguments << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << c.arguments << ": "
                               << r.out;  // refused before any pose was solved
  }
  EXPECT_EQ(read_file(model), before);
  EXPECT_EQ(read_file(poses), "h\n0.1\n");
  EXPECT_FALSE(fs::exists(csv));
}

TEST_F(Cli, SweepPlotsAMatrixEntryWithoutFull) {
  const fs::path csv = folder_ / "c.csv";
  const CliRun r = run("sweep " + example_path("planar-3rpr-parametric.yaml") +
                       " --grid x=0.3:0.6:3 --plot --plot-column platform.C66 --csv " +
                       shell_quoted(csv.string()));
  ASSERT_EQ(r.exit_code, exit_success) << r.err;
  EXPECT_GT(fs::file_size(folder_ / "c.platform.C66.png"), 1000u);
  EXPECT_FALSE(contains(read_file(csv), "C66"));  // the rows stay the short ones
}

TEST_F(Cli, SolveTakesParameterValues) {
  const fs::path json = folder_ / "r.json";
  const CliRun r = run("solve " + example_path("tripteron-parametric.yaml") +
                       " --set px=0.2 --set py=0.2 --json " + shell_quoted(json.string()));
  ASSERT_EQ(r.exit_code, exit_success) << r.err;
  const CliRun unreachable =
      run("solve " + example_path("tripteron-parametric.yaml") + " --set px=0.9");
  EXPECT_EQ(unreachable.exit_code, exit_invalid_input);
  EXPECT_TRUE(contains(unreachable.err, "derived.")) << unreachable.err;
  // Where the failing derived value is defined, and not again at each number that uses it.
  EXPECT_TRUE(contains(unreachable.err, "tripteron-parametric.yaml:42:11: derived.y_side"))
      << unreachable.err;
  EXPECT_FALSE(contains(unreachable.err, "points.elbow_y")) << unreachable.err;
}

TEST_F(Cli, SummaryNamesTheSolverAndWhyNoConditionIsEstimated) {
  const CliRun serial = run("solve " + example_path("industrial-6axis.yaml"));
  ASSERT_EQ(serial.exit_code, exit_success) << serial.err;
  EXPECT_TRUE(contains(serial.out, "(solver tree)")) << serial.out;
  EXPECT_TRUE(contains(serial.out,
                       "reciprocal condition: not estimated (the tree solve factorises nothing)"))
      << serial.out;
  const CliRun parallel = run("solve " + example_path("tripteron.yaml"));
  ASSERT_EQ(parallel.exit_code, exit_success) << parallel.err;
  EXPECT_TRUE(contains(parallel.out, "(solver tree_with_cuts)")) << parallel.out;
  EXPECT_TRUE(contains(
      parallel.out,
      "reciprocal condition: not estimated (the tree solve with cuts factorises no sparse system)"))
      << parallel.out;
  const CliRun forced = run("solve " + example_path("tripteron.yaml") + " --solver sparse_lu");
  ASSERT_EQ(forced.exit_code, exit_success) << forced.err;
  EXPECT_TRUE(contains(forced.out, "(solver sparse_lu)")) << forced.out;
  EXPECT_TRUE(contains(forced.out, "(condition number about")) << forced.out;
}

// ---- view, --vtk and check's geometry (docs/viewer.md) ------------------------------------

TEST_F(Cli, ViewWritesOnePageBesideTheModel) {
  const fs::path model = write_model("cantilever.yaml", cantilever_model);
  const CliRun r = run("view " + shell_quoted(model.string()));
  ASSERT_EQ(r.exit_code, exit_success) << r.err;
  const std::string page = read_file(folder_ / "cantilever.html");
  EXPECT_TRUE(contains(page, "id=\"stiffmsa-data\"")) << page.substr(0, 200);
  EXPECT_TRUE(contains(r.out, "cantilever.html")) << r.out;
}

TEST_F(Cli, ViewRefusesToWriteOverTheModel) {
  const fs::path model = write_model("cantilever.yaml", cantilever_model);
  const CliRun r =
      run("view " + shell_quoted(model.string()) + " -o " + shell_quoted(model.string()));
  EXPECT_EQ(r.exit_code, exit_invalid_input);
  EXPECT_EQ(read_file(model), cantilever_model);
}

TEST_F(Cli, ViewOfAMechanismStillShowsTheModel) {
  const fs::path model = write_model("floating.yaml", unsupported_model);
  const fs::path page = folder_ / "floating.html";
  const CliRun r =
      run("view " + shell_quoted(model.string()) + " -o " + shell_quoted(page.string()));
  EXPECT_EQ(r.exit_code, exit_cannot_solve) << r.err;
  EXPECT_TRUE(contains(read_file(page), "\"solved\":false"));
}

// `view --case NAME` draws that case's loads and deflections, and names the case in the title.
TEST_F(Cli, ViewDrawsTheNamedLoadCaseAndRefusesAnUnknownOne) {
  const fs::path model = write_model("cases.yaml", R"(format: stiffmsa/1
name: cases
materials: {steel: {E: 2.1e11, nu: 0.3}}
sections: {tube: {shape: tube, D: 0.06, t: 0.004}}
points: {root: [0, 0, 0], tip: [1.2, 0, 0]}
links: {arm: {type: beam, from: root, to: tip, material: steel, section: tube}}
supports: {clamp: {type: rigid, at: root}}
load_cases:
  down: [{at: tip, wrench: [0, 0, -500, 0, 0, 0]}]
  sideways: [{link: arm, distributed: [0, 300, 0]}]
end_effectors: {end: {at: tip}}
)");
  const fs::path down = folder_ / "down.html", sideways = folder_ / "sideways.html";
  const CliRun first = run("view " + shell_quoted(model.string()) + " --case down -o " +
                           shell_quoted(down.string()));
  ASSERT_EQ(first.exit_code, exit_success) << first.err;
  const CliRun second = run("view " + shell_quoted(model.string()) + " --case sideways -o " +
                            shell_quoted(sideways.string()));
  ASSERT_EQ(second.exit_code, exit_success) << second.err;
  const std::string down_page = read_file(down), sideways_page = read_file(sideways);
  EXPECT_TRUE(contains(down_page, "load case: down")) << down_page.substr(0, 400);
  EXPECT_TRUE(contains(sideways_page, "load case: sideways"));
  EXPECT_NE(down_page, sideways_page);
  const fs::path other = folder_ / "other.html";
  const CliRun unknown =
      run("view " + shell_quoted(model.string()) + " --case up -o " + shell_quoted(other.string()));
  EXPECT_EQ(unknown.exit_code, exit_invalid_input);
  EXPECT_TRUE(contains(unknown.err, "--case 'up'")) << unknown.err;
  EXPECT_TRUE(contains(unknown.err, "'down', 'sideways'")) << unknown.err;
  EXPECT_FALSE(fs::exists(other));
}

TEST_F(Cli, SolveWritesAParaViewFileAndRefusesAnotherExtension) {
  const fs::path model = write_model("cantilever.yaml", cantilever_model);
  const CliRun r = run("solve " + shell_quoted(model.string()) + " --vtk " +
                       shell_quoted((folder_ / "c.vtu").string()));
  ASSERT_EQ(r.exit_code, exit_success) << r.err;
  EXPECT_TRUE(contains(read_file(folder_ / "c.vtu"), "<VTKFile type=\"UnstructuredGrid\""));
  const CliRun wrong = run("solve " + shell_quoted(model.string()) + " --vtk " +
                           shell_quoted((folder_ / "c.vtk").string()));
  EXPECT_EQ(wrong.exit_code, exit_invalid_input);
  EXPECT_TRUE(contains(wrong.err, ".vtu")) << wrong.err;
}

TEST_F(Cli, CheckListsLinkLengthsAndJointAxes) {
  const CliRun r = run("check " + example_path("planar-3rpr.yaml"));
  ASSERT_EQ(r.exit_code, exit_success) << r.err;
  EXPECT_TRUE(contains(r.out, "Links (length in m):")) << r.out;
  EXPECT_TRUE(contains(r.out, "platform_1     rigid       0.120341     centre -> P1")) << r.out;
  EXPECT_TRUE(contains(r.out, "pin_1          at P1: revolute, passive, axis (0, 0, 1)")) << r.out;
  EXPECT_TRUE(contains(r.out, "actuator_1     at M1: prismatic, actuated, axis (")) << r.out;
}

// ---- what was fixed, plausibility, and the small things a user notices (issue 18) -------------

TEST_F(Cli, SolveRecordsTheParametersSetAndAtTheirDefaults) {
  const fs::path json = folder_ / "r.json";
  const CliRun r = run("solve " + example_path("planar-3rpr-parametric.yaml") +
                       " --set y=0.35 --json " + shell_quoted(json.string()));
  ASSERT_EQ(r.exit_code, exit_success) << r.err;
  EXPECT_TRUE(contains(r.out, "Parameters: x = 0.46 m, y = 0.35 m (set), phi = 0.0831 rad"))
      << r.out;
  const auto result = nlohmann::json::parse(read_file(json));
  EXPECT_EQ(result["parameters"]["y"]["value"], 0.35);
  EXPECT_EQ(result["parameters"]["y"]["set"], true);
  EXPECT_EQ(result["parameters"]["x"]["value"], 0.46);
  EXPECT_EQ(result["parameters"]["x"]["set"], false);
  // Without --set, the defaults are recorded too; a model without parameters records none.
  ASSERT_EQ(run("solve " + example_path("planar-3rpr-parametric.yaml") + " --json " +
                shell_quoted(json.string()))
                .exit_code,
            exit_success);
  EXPECT_EQ(nlohmann::json::parse(read_file(json))["parameters"]["y"]["set"], false);
  const CliRun plain =
      run("solve " + example_path("cantilever.yaml") + " --json " + shell_quoted(json.string()));
  ASSERT_EQ(plain.exit_code, exit_success) << plain.err;
  EXPECT_FALSE(contains(plain.out, "Parameters:")) << plain.out;
  EXPECT_TRUE(nlohmann::json::parse(read_file(json))["parameters"].empty());
}

TEST_F(Cli, SolveWarnsOfImplausibleValuesAndLargeDeflectionsButSucceeds) {
  std::string mpa = cantilever_model;
  mpa.replace(mpa.find("E: 2.1e11"), 9, "E: 70000");
  const fs::path model = write_model("mpa.yaml", mpa);
  const CliRun r = run("solve " + shell_quoted(model.string()));
  EXPECT_EQ(r.exit_code, exit_success) << r.err;
  EXPECT_TRUE(contains(
      r.out, "warning: " + model.string() + ":11:16: links.L1.material.E: E = 70000 Pa is below"))
      << r.out;
  EXPECT_TRUE(contains(
      r.out, "warning: the deflections under the loads are too large for the linear method"))
      << r.out;
  const CliRun checked = run("check " + shell_quoted(model.string()));
  EXPECT_EQ(checked.exit_code, exit_success);
  EXPECT_TRUE(contains(checked.out, "warning: " + model.string() + ":11:16: links.L1.material.E"))
      << checked.out;
  const CliRun near_singular =
      run("solve " + example_path("planar-3rpr-parametric.yaml") + " --set x=0.32 --set y=0.7605");
  EXPECT_EQ(near_singular.exit_code, exit_success);
  EXPECT_TRUE(contains(near_singular.out, "link end 'platform_1.from' turns")) << near_singular.out;
  const CliRun fine = run("solve " + example_path("planar-3rpr-parametric.yaml"));
  EXPECT_FALSE(contains(fine.out, "warning")) << fine.out;
}

TEST_F(Cli, SolvePrintsPrincipalDirectionsAndTheStiffnessAlongADirection) {
  const fs::path model = write_model("cantilever.yaml", cantilever_model);
  const fs::path json = folder_ / "r.json";
  const CliRun r = run("solve " + shell_quoted(model.string()) + " --direction 0,3,0 --json " +
                       shell_quoted(json.string()));
  ASSERT_EQ(r.exit_code, exit_success) << r.err;
  EXPECT_TRUE(contains(
      r.out,
      "Principal directions (unit vectors in global x, y, z; in the order of the values above)"))
      << r.out;
  EXPECT_TRUE(contains(r.out, "Stiffness along ( 0.0000,  1.0000,  0.0000)")) << r.out;
  // k = 3·E·I/L³ for the rod.
  const double bending =
      3 * youngs_modulus * std::numbers::pi * std::pow(diameter, 4) / 64 / std::pow(length, 3);
  char expected[64];
  std::snprintf(expected, sizeof expected, "against a force along it  [N/m]:     %.5e", bending);
  EXPECT_TRUE(contains(r.out, expected)) << r.out;
  EXPECT_FALSE(contains(r.out, "-0.0000")) << r.out;
  const auto result = nlohmann::json::parse(read_file(json));
  EXPECT_NEAR(result["end_effectors"]["EE"]["along_direction"]["translational"].get<double>(),
              bending, 1e-9 * bending);
  for (const char* bad : {"0,0", "0,0,0", "a,1,0", "1,2,3,4"}) {
    const CliRun refused = run("solve " + shell_quoted(model.string()) + " --direction " + bad);
    EXPECT_EQ(refused.exit_code, exit_invalid_input) << bad;
    EXPECT_TRUE(contains(refused.err, std::string("--direction '") + bad + "'")) << refused.err;
  }
  EXPECT_TRUE(contains(run("solve " + shell_quoted(model.string()) + " --direction 0,0,0").err,
                       "--direction '0,0,0': the direction must not be zero"));
  EXPECT_TRUE(contains(run("solve " + shell_quoted(model.string()) + " --direction 1,2").err,
                       "--direction '1,2': write X,Y,Z, three finite numbers, e.g. 0,0,1"));
}

TEST_F(Cli, RoundOffMomentsAndASingularSystemsConditionAreExplained) {
  const CliRun legs = run("solve " + example_path("gough-stewart-6ups.yaml"));
  ASSERT_EQ(legs.exit_code, exit_success) << legs.err;
  // The legs carry forces only: their moments are round-off, not "the largest joint moment".
  EXPECT_TRUE(contains(legs.out, "Largest joint wrench (on the first link end)\n  force:    "))
      << legs.out;
  EXPECT_TRUE(contains(legs.out, "  moment: none (every moment is zero or round-off)\n"))
      << legs.out;
  // Unloaded, every wrench is zero: nothing is "the largest".
  std::string unloaded = cantilever_model;
  unloaded.erase(unloaded.find("loads:"),
                 unloaded.find("end_effectors:") - unloaded.find("loads:"));
  const CliRun idle_rod =
      run("solve " + shell_quoted(write_model("unloaded.yaml", unloaded).string()));
  ASSERT_EQ(idle_rod.exit_code, exit_success) << idle_rod.err;
  EXPECT_TRUE(
      contains(idle_rod.out,
               "Largest support reaction\n  force:  none (every force is zero or round-off)\n"
               "  moment: none (every moment is zero or round-off)\n"))
      << idle_rod.out;
  const fs::path braced = write_model("braced.yaml", braced_arm_model);
  const CliRun idle =
      run("solve " + shell_quoted(braced.string()) + " --accept-idle-motions --solver sparse_lu");
  ASSERT_EQ(idle.exit_code, exit_success) << idle.err;
  EXPECT_TRUE(contains(
      idle.out,
      "reciprocal condition: 0 (the system is singular: it was solved with its free motions "
      "or redundant constraints removed)"))
      << idle.out;
  EXPECT_FALSE(contains(idle.out, "0.00e+00")) << idle.out;
  EXPECT_FALSE(contains(idle.out, "--accept-idle-motions")) << idle.out;
  EXPECT_TRUE(contains(idle.out, "(an idle motion, accepted)")) << idle.out;
}

TEST_F(Cli, MissingModelFileSaysWhy) {
  const CliRun r = run("solve " + shell_quoted((folder_ / "absent.yaml").string()));
  EXPECT_EQ(r.exit_code, exit_invalid_input);
  EXPECT_TRUE(contains(r.err, "absent.yaml': No such file or directory")) << r.err;
}

TEST_F(Cli, SweepRecordsWhatItHeldFixedAndCountsLargeDeflections) {
  const fs::path csv = folder_ / "m.csv";
  const CliRun r =
      run("sweep " + example_path("planar-3rpr-parametric.yaml") +
          " --grid x=0.3:0.34:5 --set y=0.7605 --threads 1 --direction 1,0,0 --plot --csv " +
          shell_quoted(csv.string()));
  ASSERT_EQ(r.exit_code, exit_success) << r.err;
  EXPECT_TRUE(contains(r.out, " (1 thread, ")) << r.out;
  EXPECT_TRUE(contains(
      r.out, "  at y = 0.7605 m (set), phi = 0.0831 rad, r = 0.12 m, k_actuator = 1.5e+07 N/m\n"))
      << r.out;
  EXPECT_TRUE(contains(r.out, "with large deflections)")) << r.out;
  EXPECT_TRUE(contains(r.out, "first pose with large deflections (x = 0.3")) << r.out;
  const std::string rows = read_file(csv);
  // Grid values as written: 0.31, not 0.31000000000000005.
  EXPECT_TRUE(contains(rows, "\n0.31,ok,")) << rows;
  EXPECT_TRUE(contains(rows, "platform.cond_trans,platform.k_trans_dir,platform.k_rot_dir"))
      << rows.substr(0, 300);
  const auto summary = nlohmann::json::parse(read_file(folder_ / "m.summary.json"));
  EXPECT_EQ(summary["fixed_parameters"]["y"]["value"], 0.7605);
  EXPECT_EQ(summary["fixed_parameters"]["y"]["set"], true);
  EXPECT_GE(summary["large_deflection"].get<int>(), 1);
  EXPECT_GT(fs::file_size(folder_ / "m.platform.deflection_trans.png"), 1000u);
}

TEST_F(Cli, ViewRefusesAScaleThatIsNotPositive) {
  const fs::path model = write_model("cantilever.yaml", cantilever_model);
  const CliRun r = run("view " + shell_quoted(model.string()) + " --scale -1");
  EXPECT_EQ(r.exit_code, exit_invalid_input);
  EXPECT_TRUE(contains(r.err, "--scale: expected a positive number, got '-1'")) << r.err;
  EXPECT_FALSE(fs::exists(folder_ / "cantilever.html"));
}
