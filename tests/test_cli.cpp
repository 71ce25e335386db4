// End to end: the stiffmsa program as a user runs it, its exit codes, messages and result file.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

constexpr int exit_success = 0;
constexpr int exit_cannot_solve = 1;
constexpr int exit_invalid_input = 2;

constexpr const char* error_prefix = "stiffmsa: error: ";

// A steel rod of 1 m clamped at O, loaded at its tip E.
constexpr double length = 1.0;
constexpr double youngs_modulus = 2.1e11;
constexpr double diameter = 0.05;
constexpr const char* cantilever_model = R"(format: stiffmsa/1
name: cantilever
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
  S1: {type: rigid, at: O, link: L1}
loads:
  - {at: E, link: L1, wrench: [0, -100, 0, 0, 0, 0]}
end_effectors:
  EE: {at: E, link: L1}
)";

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

std::string shell_quoted(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) {
    if (c == '\'') {
      quoted += "'\\''";
    } else {
      quoted += c;
    }
  }
  return quoted + "'";
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

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

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

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
  const CliRun r = run("solve " + shell_quoted(model.string()) + " --json " +
                         shell_quoted(json.string()));
  EXPECT_EQ(r.exit_code, exit_invalid_input);
  EXPECT_TRUE(contains(r.err, error_prefix)) << r.err;
  EXPECT_TRUE(contains(r.err, "Nowhere")) << r.err;
  EXPECT_FALSE(fs::exists(json));
}

TEST_F(Cli, FailedRunLeavesAnEarlierResultFileAlone) {
  const fs::path model = write_model("broken.yaml", invalid_model);
  const fs::path json = folder_ / "result.json";
  std::ofstream(json) << "earlier result";
  const CliRun r = run("solve " + shell_quoted(model.string()) + " --json " +
                         shell_quoted(json.string()));
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
  const CliRun r = run("solve " + shell_quoted(model.string()) + " --json " +
                         shell_quoted(json.string()));
  EXPECT_EQ(r.exit_code, exit_cannot_solve) << r.out << r.err;
  EXPECT_TRUE(contains(r.err, error_prefix)) << r.err;
  EXPECT_FALSE(fs::exists(json));
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
  const CliRun r = run("solve " + shell_quoted(model.string()) + " --json " +
                         shell_quoted(json.string()));
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
  const CliRun r = run("solve " + shell_quoted(model.string()) + " --json " +
                         shell_quoted(model.string()));
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
  const CliRun refused = run("solve " + shell_quoted(model.string()) + " --json " + shell_quoted(json.string()));
  EXPECT_EQ(refused.exit_code, exit_cannot_solve) << refused.out << refused.err;
  EXPECT_TRUE(contains(refused.err, "'strut'")) << refused.err;
  EXPECT_TRUE(contains(refused.err, "idle motion")) << refused.err;
  EXPECT_TRUE(contains(refused.err, "--accept-idle-motions")) << refused.err;
  EXPECT_FALSE(fs::exists(json));

  const CliRun accepted = run("solve " + shell_quoted(model.string()) + " --accept-idle-motions --json " +
                              shell_quoted(json.string()));
  ASSERT_EQ(accepted.exit_code, exit_success) << accepted.out << accepted.err;
  const auto result = nlohmann::json::parse(read_file(json));
  EXPECT_FALSE(result["end_effectors"]["tip"]["stiffness"].is_null());
  EXPECT_TRUE(result["link_ends"]["strut"]["to"]["deflection"].is_null());
  EXPECT_FALSE(result["link_ends"]["arm"]["to"]["deflection"].is_null());

  const fs::path with_option = write_model("braced-option.yaml", std::string(braced_arm_model) +
                                                                   "options: {accept_idle_motions: true}\n");
  const CliRun by_option = run("solve " + shell_quoted(with_option.string()));
  EXPECT_EQ(by_option.exit_code, exit_success) << by_option.out << by_option.err;
}
