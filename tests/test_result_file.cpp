// The result file is read by programs outside this repository: its keys, nesting, nulls and
// numbers are checked here exactly, on a result built by hand (no solver involved).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "stiffmsa/errors.hpp"
#include "stiffmsa/io/result_file.hpp"

namespace {

using stiffmsa::Mat6;
using stiffmsa::Result;
using stiffmsa::Vec6;
using stiffmsa::VecX;
using Json = nlohmann::ordered_json;
namespace fs = std::filesystem;

Vec6 vec6(double first) {
  Vec6 v;
  for (int i = 0; i < 6; ++i) v[i] = first + i;
  return v;
}

VecX vecx(std::initializer_list<double> values) {
  VecX v(static_cast<Eigen::Index>(values.size()));
  Eigen::Index i = 0;
  for (double x : values) v[i++] = x;
  return v;
}

Mat6 numbered_matrix(double scale) {
  Mat6 m;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) m(r, c) = scale * (10 * r + c + 1);
  return m;
}

std::vector<double> as_vector(const Vec6& v) { return {v.data(), v.data() + 6}; }

std::vector<std::vector<double>> as_rows(const Mat6& m) {
  std::vector<std::vector<double>> rows(6, std::vector<double>(6));
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) rows[r][c] = m(r, c);
  return rows;
}

std::vector<std::string> keys_of(const Json& object) {
  std::vector<std::string> keys;
  for (const auto& item : object.items()) keys.push_back(item.key());
  return keys;
}

// Names deliberately not in alphabetical order: the file keeps the model's order.
Result sample_result() {
  Result r;
  r.model = "sample-robot";
  r.system = {48, 50, 180};

  stiffmsa::EndEffectorResult held;
  held.name = "tool";
  held.point = "E";
  held.link = "L2";
  held.compliance = numbered_matrix(1e-7);
  held.stiffness = numbered_matrix(1e5);
  held.deflection = vec6(0.5);
  stiffmsa::EndEffectorResult free_moving;  // every optional empty
  free_moving.name = "aux";
  free_moving.point = "A";
  free_moving.link = "L1";
  r.end_effectors = {held, free_moving};

  stiffmsa::LinkResult l2;
  l2.name = "L2";
  l2.from = {vec6(1), vec6(7)};
  l2.to = {vec6(13), std::nullopt};  // an undetermined internal wrench
  stiffmsa::LinkResult l1;
  l1.name = "L1";
  r.links = {l2, l1};

  stiffmsa::JointResult revolute;
  revolute.name = "J2";
  revolute.relative_deflection = std::vector<VecX>{vecx({0.25})};
  revolute.wrench = vec6(-3);
  stiffmsa::JointResult three_ends;
  three_ends.name = "J1";
  three_ends.relative_deflection = std::vector<VecX>{vecx({1, 2, 3}), vecx({4, 5, 6})};
  three_ends.wrench = std::nullopt;
  stiffmsa::JointResult motor;
  motor.name = "M";
  motor.actuated = true;
  motor.relative_deflection = std::vector<VecX>{vecx({0.0})};
  motor.wrench = vec6(2);
  motor.effort = vecx({12.5});
  stiffmsa::JointResult undetermined_motor;
  undetermined_motor.name = "M2";
  undetermined_motor.actuated = true;
  r.joints = {revolute, three_ends, motor, undetermined_motor};

  stiffmsa::SupportResult ground;
  ground.name = "S2";
  ground.reaction = vec6(-6);
  stiffmsa::SupportResult indeterminate;
  indeterminate.name = "S1";
  r.supports = {ground, indeterminate};

  r.report.relative_residual = 1.5e-16;
  r.report.equilibrium_error = 2.5e-15;
  r.report.reciprocal_condition = 3.25e-9;
  r.report.solver = stiffmsa::SolverUsed::sparse_lu;
  r.report.notes = {"wrenches in the loop at A are undetermined"};
  return r;
}

Json parsed_sample() { return Json::parse(stiffmsa::result_to_json(sample_result())); }

TEST(ResultJson, TopLevelKeysInContractOrder) {
  const Json j = parsed_sample();
  EXPECT_EQ(keys_of(j),
            (std::vector<std::string>{"format", "model", "parameters", "system", "end_effectors",
                                      "link_ends", "joints", "supports", "report"}));
  EXPECT_EQ(j["format"], "stiffmsa-result/1");
  EXPECT_EQ(j["model"], "sample-robot");
  EXPECT_EQ(keys_of(j["system"]), (std::vector<std::string>{"unknowns", "equations", "nonzeros"}));
  EXPECT_EQ(j["system"]["unknowns"], 48);
  EXPECT_EQ(j["system"]["equations"], 50);
  EXPECT_EQ(j["system"]["nonzeros"], 180);
  EXPECT_TRUE(j["system"]["unknowns"].is_number_integer());
}

TEST(ResultJson, EndEffectorsKeepModelOrderAndWriteMatricesAsRows) {
  const Json j = parsed_sample();
  EXPECT_EQ(keys_of(j["end_effectors"]), (std::vector<std::string>{"tool", "aux"}));

  const Json& tool = j["end_effectors"]["tool"];
  EXPECT_EQ(keys_of(tool), (std::vector<std::string>{"point", "link", "compliance", "stiffness",
                                                     "deflection", "principal_stiffness"}));
  EXPECT_EQ(tool["point"], "E");
  EXPECT_EQ(tool["link"], "L2");
  EXPECT_EQ(tool["compliance"].get<std::vector<std::vector<double>>>(),
            as_rows(numbered_matrix(1e-7)));
  EXPECT_EQ(tool["stiffness"].get<std::vector<std::vector<double>>>(),
            as_rows(numbered_matrix(1e5)));
  // Row-major: the second row's first entry is m(1, 0).
  EXPECT_EQ(tool["stiffness"][1][0].get<double>(), 1e5 * 11);
  EXPECT_EQ(tool["deflection"].get<std::vector<double>>(), as_vector(vec6(0.5)));
}

TEST(ResultJson, EmptyOptionalsAreWholeNulls) {
  const Json j = parsed_sample();
  const Json& aux = j["end_effectors"]["aux"];
  EXPECT_EQ(keys_of(aux), (std::vector<std::string>{"point", "link", "compliance", "stiffness",
                                                    "deflection", "principal_stiffness"}));
  EXPECT_TRUE(aux["compliance"].is_null());
  EXPECT_TRUE(aux["principal_stiffness"].is_null());
  EXPECT_TRUE(aux["stiffness"].is_null());
  EXPECT_TRUE(aux["deflection"].is_null());

  EXPECT_TRUE(j["link_ends"]["L2"]["to"]["wrench"].is_null());
  EXPECT_TRUE(j["link_ends"]["L1"]["from"]["deflection"].is_null());
  EXPECT_TRUE(j["link_ends"]["L1"]["to"]["wrench"].is_null());
  EXPECT_TRUE(j["joints"]["J1"]["wrench"].is_null());
  EXPECT_TRUE(j["joints"]["M2"]["relative_deflection"].is_null());
  EXPECT_TRUE(j["joints"]["M2"]["wrench"].is_null());
  EXPECT_TRUE(j["supports"]["S1"]["reaction"].is_null());
}

TEST(ResultJson, LinkEnds) {
  const Json j = parsed_sample();
  EXPECT_EQ(keys_of(j["link_ends"]), (std::vector<std::string>{"L2", "L1"}));
  const Json& l2 = j["link_ends"]["L2"];
  EXPECT_EQ(keys_of(l2), (std::vector<std::string>{"from", "to"}));
  EXPECT_EQ(keys_of(l2["from"]), (std::vector<std::string>{"deflection", "wrench"}));
  EXPECT_EQ(l2["from"]["deflection"].get<std::vector<double>>(), as_vector(vec6(1)));
  EXPECT_EQ(l2["from"]["wrench"].get<std::vector<double>>(), as_vector(vec6(7)));
  EXPECT_EQ(l2["to"]["deflection"].get<std::vector<double>>(), as_vector(vec6(13)));
}

TEST(ResultJson, JointsTwoEndsFlatMoreEndsListOfLists) {
  const Json j = parsed_sample();
  EXPECT_EQ(keys_of(j["joints"]), (std::vector<std::string>{"J2", "J1", "M", "M2"}));

  const Json& two_ends = j["joints"]["J2"];
  EXPECT_EQ(keys_of(two_ends), (std::vector<std::string>{"relative_deflection", "wrench"}));
  EXPECT_EQ(two_ends["relative_deflection"].get<std::vector<double>>(), std::vector<double>{0.25});
  EXPECT_EQ(two_ends["wrench"].get<std::vector<double>>(), as_vector(vec6(-3)));

  const Json& three_ends = j["joints"]["J1"];
  ASSERT_TRUE(three_ends["relative_deflection"].is_array());
  EXPECT_EQ(three_ends["relative_deflection"].get<std::vector<std::vector<double>>>(),
            (std::vector<std::vector<double>>{{1, 2, 3}, {4, 5, 6}}));
}

TEST(ResultJson, EffortOnlyForActuatedJoints) {
  const Json j = parsed_sample();
  EXPECT_FALSE(j["joints"]["J2"].contains("effort"));
  EXPECT_FALSE(j["joints"]["J1"].contains("effort"));
  EXPECT_EQ(keys_of(j["joints"]["M"]),
            (std::vector<std::string>{"relative_deflection", "wrench", "effort"}));
  EXPECT_EQ(j["joints"]["M"]["effort"].get<std::vector<double>>(), std::vector<double>{12.5});
  ASSERT_TRUE(j["joints"]["M2"].contains("effort"));
  EXPECT_TRUE(j["joints"]["M2"]["effort"].is_null());
}

TEST(ResultJson, SupportsAndReport) {
  const Json j = parsed_sample();
  EXPECT_EQ(keys_of(j["supports"]), (std::vector<std::string>{"S2", "S1"}));
  EXPECT_EQ(keys_of(j["supports"]["S2"]), (std::vector<std::string>{"reaction"}));
  EXPECT_EQ(j["supports"]["S2"]["reaction"].get<std::vector<double>>(), as_vector(vec6(-6)));

  const Json& report = j["report"];
  EXPECT_EQ(report["solver"], "sparse_lu");
  EXPECT_EQ(report["relative_residual"].get<double>(), 1.5e-16);
  EXPECT_EQ(report["equilibrium_error"].get<double>(), 2.5e-15);
  EXPECT_EQ(report["reciprocal_condition"].get<double>(), 3.25e-9);
  EXPECT_EQ(report["notes"].get<std::vector<std::string>>(),
            std::vector<std::string>{"wrenches in the loop at A are undetermined"});
  EXPECT_TRUE(report["warnings"].is_array());
  EXPECT_TRUE(report["warnings"].empty());
}

TEST(ResultJson, EmptyModelStillHasEveryKey) {
  Result empty;
  empty.model = "nothing";
  const Json j = Json::parse(stiffmsa::result_to_json(empty));
  for (const char* key : {"end_effectors", "link_ends", "joints", "supports"}) {
    ASSERT_TRUE(j.contains(key)) << key;
    EXPECT_TRUE(j[key].is_object()) << key;
    EXPECT_TRUE(j[key].empty()) << key;
  }
}

TEST(ResultJson, NumbersRoundTripExactly) {
  const std::vector<double> awkward = {
      0.1,
      1.0 / 3.0,
      -2.0 / 3.0 * 1e-300,
      std::nextafter(1.0, 2.0),
      std::numeric_limits<double>::denorm_min(),
      std::numeric_limits<double>::max(),
      -1.2345678901234567e-7,
  };
  Result r;
  r.model = "numbers";
  stiffmsa::EndEffectorResult e;
  e.name = "EE";
  Mat6 m = Mat6::Zero();
  for (std::size_t i = 0; i < awkward.size(); ++i) {
    m(static_cast<int>(i % 6), static_cast<int>(i / 6)) = awkward[i];
  }
  e.compliance = m;
  r.end_effectors = {e};
  r.report.relative_residual = awkward[3];

  const Json j = Json::parse(stiffmsa::result_to_json(r));
  const auto rows = j["end_effectors"]["EE"]["compliance"].get<std::vector<std::vector<double>>>();
  for (std::size_t i = 0; i < awkward.size(); ++i) {
    EXPECT_EQ(rows[i % 6][i / 6], awkward[i]) << "value " << i;
  }
  EXPECT_EQ(j["report"]["relative_residual"].get<double>(), awkward[3]);
}

TEST(ResultJson, NamesAreEscaped) {
  Result r;
  r.model = "quote \" backslash \\ newline \n end";
  stiffmsa::SupportResult s;
  s.name = "S \"1\"";
  r.supports = {s};
  const Json j = Json::parse(stiffmsa::result_to_json(r));
  EXPECT_EQ(j["model"], r.model);
  EXPECT_TRUE(j["supports"].contains("S \"1\""));
}

// ---- atomic writes ---------------------------------------------------------------------

class AtomicFile : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    folder_ = fs::temp_directory_path() /
              ("stiffmsa-test-result-file-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  static std::string read(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

  std::vector<std::string> files_in(const fs::path& folder) const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(folder)) {
      names.push_back(entry.path().filename().string());
    }
    return names;
  }

  fs::path folder_;
};

TEST_F(AtomicFile, WritesTheWholeContents) {
  std::string contents;
  for (int i = 0; i < 200000; ++i) contents += static_cast<char>('a' + i % 26);
  contents += std::string("\0binary\0", 8);
  const fs::path target = folder_ / "out.json";
  stiffmsa::write_file_atomically(target, contents);
  EXPECT_EQ(read(target), contents);
  EXPECT_EQ(files_in(folder_), std::vector<std::string>{"out.json"});
}

TEST_F(AtomicFile, ReplacesAnExistingFile) {
  const fs::path target = folder_ / "out.json";
  std::ofstream(target) << "an older and longer content that must disappear entirely";
  const auto owner_only = fs::perms::owner_read | fs::perms::owner_write;
  fs::permissions(target, owner_only);
  stiffmsa::write_file_atomically(target, "new");
  EXPECT_EQ(read(target), "new");
  // Replacing a file keeps who may read it.
  EXPECT_EQ(fs::status(target).permissions(), owner_only);
  EXPECT_EQ(files_in(folder_), std::vector<std::string>{"out.json"});
}

TEST_F(AtomicFile, MissingFolderThrowsIoErrorAndLeavesNothing) {
  const fs::path target = folder_ / "no-such-folder" / "out.json";
  try {
    stiffmsa::write_file_atomically(target, "contents");
    FAIL() << "expected IoError";
  } catch (const stiffmsa::IoError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(target.string()), std::string::npos) << message;
    EXPECT_NE(message.find("No such file or directory"), std::string::npos) << message;
  }
  EXPECT_FALSE(fs::exists(target));
  EXPECT_TRUE(files_in(folder_).empty());
}

TEST_F(AtomicFile, TargetThatIsAFolderThrowsAndLeavesNoTemporaryFile) {
  const fs::path target = folder_ / "taken";
  fs::create_directory(target);
  EXPECT_THROW(stiffmsa::write_file_atomically(target, "contents"), stiffmsa::IoError);
  EXPECT_TRUE(fs::is_directory(target));
  EXPECT_EQ(files_in(folder_), std::vector<std::string>{"taken"});
}

TEST_F(AtomicFile, PathWithoutFileNameThrows) {
  EXPECT_THROW(stiffmsa::write_file_atomically(folder_ / "", "contents"), stiffmsa::IoError);
  EXPECT_THROW(stiffmsa::write_file_atomically("", "contents"), stiffmsa::IoError);
}

TEST_F(AtomicFile, WriteResultFileWritesTheJson) {
  const fs::path target = folder_ / "result.json";
  stiffmsa::write_result_file(sample_result(), target);
  EXPECT_EQ(read(target), stiffmsa::result_to_json(sample_result()));
  EXPECT_EQ(Json::parse(read(target))["format"], "stiffmsa-result/1");
}

}  // namespace
