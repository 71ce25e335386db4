// Hostile and invalid input: every file of the corpus in tests/invalid is refused before any
// solve, by the command and by the library, with exactly the messages its manifest
// (tests/invalid/expectations.txt) lists; files beyond the limits on size, nesting and entity
// counts are refused at once, with the option that raises the limit; and a 100 000-link chain,
// far above real models, still loads.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "builders.hpp"
#include "command_line.hpp"
#include "stiffmsa/io/model_file.hpp"

namespace stiffmsa {
namespace {

namespace fs = std::filesystem;
using stiffmsa::testing::contains;
using stiffmsa::testing::read_file;
using stiffmsa::testing::shell_quoted;

constexpr int exit_success = 0;
constexpr int exit_invalid_input = 2;
constexpr const char* error_prefix = "stiffmsa: error: ";

const fs::path corpus_folder = fs::path(STIFFMSA_SOURCE_DIR) / "tests" / "invalid";

// A valid model: a steel rod clamped at O and loaded at E.
constexpr const char* cantilever_model = stiffmsa::testing::kCantileverYaml;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string trimmed(const std::string& text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t") + 1 - first);
}

// ---- the command, run as a user runs it ----------------------------------------------------

struct CliRun {
  int exit_code = -1;  // -1 unless the program exited by itself
  int signal = 0;      // the signal that ended it, if one did
  bool timed_out = false;
  std::string out;
  std::string err;
};

// Runs the stiffmsa program with `arguments` and no stdin, its output going to files in
// `folder`. A run that takes longer than `timeout` is killed: a hang fails, it does not block.
CliRun run_cli(const std::vector<std::string>& arguments, const fs::path& folder,
               std::chrono::seconds timeout = std::chrono::seconds(60)) {
  const fs::path out = folder / "stdout.txt";
  const fs::path err = folder / "stderr.txt";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<std::string> words{STIFFMSA_CLI};
  words.insert(words.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (auto& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);

  CliRun run;
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, STIFFMSA_CLI, &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    ADD_FAILURE() << "cannot start " << STIFFMSA_CLI;
    return run;
  }
  int status = 0;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      run.timed_out = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (!run.timed_out && WIFEXITED(status)) run.exit_code = WEXITSTATUS(status);
  if (!run.timed_out && WIFSIGNALED(status)) run.signal = WTERMSIG(status);
  run.out = read_file(out);
  run.err = read_file(err);
  return run;
}

// A refusal: exit code 2 by the program's own hand (no signal, no hang), nothing on stdout.
::testing::AssertionResult refused(const CliRun& run) {
  if (run.timed_out) return ::testing::AssertionFailure() << "the program did not finish";
  if (run.signal != 0)
    return ::testing::AssertionFailure()
           << "the program was killed by signal " << run.signal << "\n"
           << run.err;
  if (run.exit_code != exit_invalid_input)
    return ::testing::AssertionFailure()
           << "exit code " << run.exit_code << ", expected " << exit_invalid_input << "\n"
           << run.err << run.out;
  if (!run.out.empty()) return ::testing::AssertionFailure() << "printed:\n" << run.out;
  return ::testing::AssertionSuccess();
}

// A folder of its own for each test, removed after it.
class TempFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(info->test_suite_name()) + "-" + info->name();
    std::replace(name.begin(), name.end(), '/', '-');
    folder_ = fs::temp_directory_path() /
              ("stiffmsa-test-invalid-" + std::to_string(::getpid()) + "-" + name);
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  fs::path write(const std::string& file_name, const std::string& text) const {
    const fs::path path = folder_ / file_name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }

  fs::path folder_;
};

// ---- the manifest --------------------------------------------------------------------------

// One message a corpus file must give (expectations.txt explains the format).
struct Expectation {
  std::string file;
  std::string key_path;  // empty: none
  int line = 0;          // 0: none
  int column = 0;
  std::vector<std::string> words;
};

std::vector<Expectation> read_manifest() {
  std::vector<Expectation> expectations;
  std::ifstream in(corpus_folder / "expectations.txt");
  for (std::string text; std::getline(in, text);) {
    if (trimmed(text).empty() || trimmed(text)[0] == '#') continue;
    std::vector<std::string> fields;
    std::istringstream row(text);
    for (std::string field; std::getline(row, field, '|');) fields.push_back(trimmed(field));
    if (fields.size() < 3) {
      ADD_FAILURE() << "expectations.txt: a line needs FILE | KEY PATH | LINE:COLUMN: " << text;
      continue;
    }
    Expectation e;
    e.file = fields[0];
    if (fields[1] != "-") e.key_path = fields[1];
    if (fields[2] != "-" && std::sscanf(fields[2].c_str(), "%d:%d", &e.line, &e.column) != 2)
      ADD_FAILURE() << "expectations.txt: not LINE:COLUMN: " << fields[2];
    e.words.assign(fields.begin() + 3, fields.end());
    expectations.push_back(std::move(e));
  }
  return expectations;
}

std::vector<Expectation> expectations_for(const std::string& file) {
  std::vector<Expectation> found;
  for (auto& e : read_manifest())
    if (e.file == file) found.push_back(std::move(e));
  return found;
}

std::vector<std::string> manifest_files() {
  std::vector<std::string> files;
  for (const auto& e : read_manifest())
    if (std::find(files.begin(), files.end(), e.file) == files.end()) files.push_back(e.file);
  return files;
}

std::vector<std::string> corpus_files() {
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(corpus_folder)) {
    const std::string extension = entry.path().extension().string();
    if (extension == ".yaml" || extension == ".json")
      files.push_back(entry.path().filename().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// "file:line:column: key.path: " as a message of the command begins (model.hpp, Diagnostic).
std::string message_start(const std::string& path, const Expectation& e) {
  std::string start = path;
  if (e.line > 0) start += ":" + std::to_string(e.line) + ":" + std::to_string(e.column);
  start += ": ";
  if (!e.key_path.empty()) start += e.key_path + ": ";
  return start;
}

bool has_every_word(const std::string& text, const std::vector<std::string>& words) {
  return std::all_of(words.begin(), words.end(),
                     [&](const std::string& w) { return contains(text, w); });
}

std::string described(const Expectation& e) {
  std::string text = e.key_path.empty() ? "(no key)" : e.key_path;
  text += " at " + std::to_string(e.line) + ":" + std::to_string(e.column) + " with";
  for (const auto& w : e.words) text += " [" + w + "]";
  return text;
}

TEST(InvalidCorpusManifest, ListsEveryFileOfTheCorpusAndNoOther) {
  const auto in_folder = corpus_files();
  auto in_manifest = manifest_files();
  std::sort(in_manifest.begin(), in_manifest.end());
  EXPECT_EQ(in_folder, in_manifest);
  EXPECT_GE(in_folder.size(), 30u);
  EXPECT_GE(std::count_if(in_folder.begin(), in_folder.end(),
                          [](const std::string& f) { return fs::path(f).extension() == ".json"; }),
            3);
  EXPECT_GE(expectations_for("several-defects.yaml").size(), 5u);
}

// ---- every corpus file, through the command and the library ---------------------------------

class InvalidCorpus : public TempFolder, public ::testing::WithParamInterface<std::string> {};

TEST_P(InvalidCorpus, IsRefusedByTheCommandWithEachExpectedMessage) {
  const std::string file = GetParam();
  const std::string path = (corpus_folder / file).string();
  const auto expectations = expectations_for(file);
  ASSERT_FALSE(expectations.empty());
  const fs::path result = folder_ / "result.json";

  const CliRun run = run_cli({"solve", path, "--json", result.string()}, folder_);
  EXPECT_TRUE(refused(run));
  EXPECT_FALSE(fs::exists(result)) << "a result file was written for an invalid model";

  const auto lines = lines_of(run.err);
  for (const auto& line : lines) EXPECT_EQ(line.rfind(error_prefix, 0), 0u) << line;
  EXPECT_EQ(lines.size(), expectations.size()) << "one message per defect, got:\n" << run.err;
  for (const auto& e : expectations) {
    const std::string start = error_prefix + message_start(path, e);
    const bool found = std::any_of(lines.begin(), lines.end(), [&](const std::string& line) {
      return line.rfind(start, 0) == 0 && has_every_word(line, e.words);
    });
    EXPECT_TRUE(found) << "no message starting '" << start << "' for " << described(e) << " in:\n"
                       << run.err;
  }
}

TEST_P(InvalidCorpus, IsRefusedByTheLibraryWithEachExpectedDiagnostic) {
  const std::string file = GetParam();
  const std::string path = (corpus_folder / file).string();
  const auto expectations = expectations_for(file);
  std::vector<Diagnostic> diagnostics;
  try {
    load_model(path);
    FAIL() << file << " was accepted";
  } catch (const InputError& e) {
    diagnostics = e.diagnostics();
  }
  std::string listing;
  for (const auto& d : diagnostics) listing += "  " + d.to_string() + "\n";
  EXPECT_EQ(diagnostics.size(), expectations.size()) << listing;
  for (const auto& e : expectations) {
    const bool found =
        std::any_of(diagnostics.begin(), diagnostics.end(), [&](const Diagnostic& d) {
          return d.location.file == path && d.key_path == e.key_path && d.location.line == e.line &&
                 d.location.column == e.column && has_every_word(d.message, e.words);
        });
    EXPECT_TRUE(found) << "no diagnostic " << described(e) << " in:\n" << listing;
  }
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = info.param;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(Files, InvalidCorpus, ::testing::ValuesIn(manifest_files()), test_name);

// ---- limits --------------------------------------------------------------------------------

using Limits = TempFolder;

// The one diagnostic of a refused text.
Diagnostic refusal_of(const std::string& text, const LoadLimits& limits,
                      const std::string& file = "model.yaml") {
  try {
    parse_model(text, file, limits);
  } catch (const InputError& e) {
    EXPECT_EQ(e.diagnostics().size(), 1u) << e.what();
    if (!e.diagnostics().empty()) return e.diagnostics().front();
  }
  ADD_FAILURE() << "the text was accepted";
  return {};
}

TEST_F(Limits, DefaultsAreFarAboveRealModels) {
  const LoadLimits defaults;
  EXPECT_EQ(defaults.max_file_bytes, 64u * 1024 * 1024);
  EXPECT_EQ(defaults.max_nesting_depth, 64);
  EXPECT_EQ(defaults.max_entities, 1'000'000u);
}

TEST_F(Limits, FileAboveTheSizeLimitIsRefusedAndTheOptionRaisesIt) {
  const fs::path model = write("rod.yaml", cantilever_model);
  const auto size = std::to_string(fs::file_size(model));
  const fs::path result = folder_ / "result.json";

  const CliRun small = run_cli(
      {"solve", model.string(), "--max-file-size", "100", "--json", result.string()}, folder_);
  EXPECT_TRUE(refused(small));
  EXPECT_FALSE(fs::exists(result));
  EXPECT_TRUE(contains(small.err, model.string() + ": the model file is " + size + " bytes"))
      << small.err;
  EXPECT_TRUE(contains(small.err, "above the limit of 100 bytes")) << small.err;
  EXPECT_TRUE(contains(small.err, "--max-file-size")) << small.err;

  const CliRun check_small = run_cli({"check", model.string(), "--max-file-size", "100"}, folder_);
  EXPECT_TRUE(refused(check_small));
  EXPECT_TRUE(contains(check_small.err, "--max-file-size")) << check_small.err;

  // With a unit, as the help says.
  const CliRun raised = run_cli(
      {"solve", model.string(), "--max-file-size", "1KiB", "--json", result.string()}, folder_);
  EXPECT_EQ(raised.exit_code, exit_success) << raised.err;
  EXPECT_TRUE(fs::exists(result));

  LoadLimits limits;
  limits.max_file_bytes = 100;
  EXPECT_THROW(load_model(model, limits), InputError);
  const Diagnostic d = refusal_of(cantilever_model, limits, "rod.yaml");
  EXPECT_EQ(d.location.file, "rod.yaml");
  EXPECT_TRUE(contains(d.message, size + " bytes, above the limit of 100 bytes")) << d.message;
  EXPECT_TRUE(contains(d.message, "LoadLimits::max_file_bytes")) << d.message;
  limits.max_file_bytes = 1024;
  EXPECT_EQ(load_model(model, limits).name, "cantilever");
}

TEST_F(Limits, HugeFileIsRefusedBeforeItIsRead) {
  // 70 MB, above the default limit of 64 MiB; sparse, so it costs no disk. Reading it into
  // the parser would take gigabytes of memory.
  const fs::path huge = folder_ / "huge.yaml";
  std::ofstream(huge).put('#');
  fs::resize_file(huge, 70'000'000);
  const fs::path result = folder_ / "result.json";

  const auto start = std::chrono::steady_clock::now();
  const CliRun run = run_cli({"solve", huge.string(), "--json", result.string()}, folder_);
  const auto took = std::chrono::steady_clock::now() - start;
  EXPECT_TRUE(refused(run));
  EXPECT_FALSE(fs::exists(result));
  EXPECT_TRUE(contains(run.err,
                       "the model file is 70000000 bytes (66.8 MiB), above the limit of "
                       "67108864 bytes (64.0 MiB)"))
      << run.err;
  EXPECT_TRUE(contains(run.err, "--max-file-size")) << run.err;
  EXPECT_LT(took, std::chrono::seconds(10));

  EXPECT_THROW(load_model(huge), InputError);
}

TEST_F(Limits, EndlessInputIsReadOnlyUpToTheLimit) {
  // A device has no size to ask for; it is read up to the limit and no further.
  LoadLimits limits;
  limits.max_file_bytes = 1 << 20;
  try {
    load_model("/dev/zero", limits);
    FAIL() << "/dev/zero was accepted";
  } catch (const InputError& e) {
    ASSERT_EQ(e.diagnostics().size(), 1u);
    EXPECT_EQ(e.diagnostics()[0].location.file, "/dev/zero");
    EXPECT_TRUE(
        contains(e.diagnostics()[0].message, "larger than the limit of 1048576 bytes (1.0 MiB)"))
        << e.what();
  }
}

TEST_F(Limits, DeepFlowNestingIsRefusedWithoutOverflowingTheStack) {
  // A reader that recursed once per level would overflow the stack on 100 000 levels.
  const std::string text = "format: stiffmsa/1\nx-note: " + std::string(100'000, '[') + "\n";
  const fs::path deep = write("deep.yaml", text);
  const fs::path result = folder_ / "result.json";

  const CliRun run = run_cli({"solve", deep.string(), "--json", result.string()}, folder_);
  EXPECT_TRUE(refused(run));
  EXPECT_FALSE(fs::exists(result));
  // The top-level mapping is level 1; the 64th `[` (column 8 + 64) is level 65.
  EXPECT_TRUE(contains(run.err, deep.string() + ":2:72: mappings and lists nest deeper here "
                                                "than the limit of 64 levels (the file reaches "
                                                "100001)"))
      << run.err;
  EXPECT_TRUE(contains(run.err, "--max-depth")) << run.err;

  const Diagnostic d = refusal_of(text, LoadLimits{});
  EXPECT_EQ(d.location.line, 2);
  EXPECT_EQ(d.location.column, 72);
  EXPECT_TRUE(contains(d.message, "LoadLimits::max_nesting_depth")) << d.message;

  // Nothing but brackets, and the same in JSON's braces.
  const Diagnostic brackets = refusal_of(std::string(100'000, '['), LoadLimits{}, "b.json");
  EXPECT_EQ(brackets.location.line, 1);
  EXPECT_EQ(brackets.location.column, 65);
  const Diagnostic braces = refusal_of(std::string(100'000, '{'), LoadLimits{}, "b.json");
  EXPECT_EQ(braces.location.column, 65);
}

TEST_F(Limits, DeepBlockNestingIsRefused) {
  // Line n + 2 is a key indented n levels: line 66 (column 129) is level 65.
  std::string indented = "format: stiffmsa/1\nx-note:\n";
  for (int level = 1; level < 5000; ++level)
    indented +=
        std::string(2 * static_cast<std::size_t>(level), ' ') + "k" + std::to_string(level) + ":\n";
  const Diagnostic d = refusal_of(indented, LoadLimits{});
  EXPECT_EQ(d.location.line, 66);
  EXPECT_EQ(d.location.column, 129);
  EXPECT_TRUE(contains(d.message, "the file reaches 5000")) << d.message;

  // Items of items on one line: each `- ` opens a list.
  std::string items = "format: stiffmsa/1\nx-note:\n  ";
  for (int level = 0; level < 5000; ++level) items += "- ";
  items += "x\n";
  const Diagnostic item_depth = refusal_of(items, LoadLimits{});
  EXPECT_EQ(item_depth.location.line, 3);
  EXPECT_TRUE(contains(item_depth.message, "limit of 64 levels")) << item_depth.message;

  const CliRun run = run_cli({"check", write("items.yaml", items).string()}, folder_);
  EXPECT_TRUE(refused(run));
  EXPECT_TRUE(contains(run.err, "--max-depth")) << run.err;
}

TEST_F(Limits, QuotedTextCommentsAndBlockScalarsDoNotNest) {
  const std::string brackets(500, '[');
  const std::string text = std::string(cantilever_model) + "x-quoted: \"" + brackets +
                           "\"\nx-single: '" + brackets + "'\nx-text: |\n  " + brackets + "\n  " +
                           brackets + "\n# " + brackets + "\n";
  EXPECT_EQ(parse_model(text, "notes.yaml").name, "cantilever");
}

TEST_F(Limits, RaisingTheDepthLimitLoadsTheSameFile) {
  // 70 levels in a note the loader ignores: above the default limit, valid otherwise.
  const std::string text = std::string(cantilever_model) + "x-note: " + std::string(69, '[') +
                           std::string(69, ']') + "\n";
  const fs::path model = write("noted.yaml", text);

  const CliRun run = run_cli({"check", model.string()}, folder_);
  EXPECT_TRUE(refused(run));
  EXPECT_TRUE(contains(run.err, "the file reaches 70")) << run.err;
  const CliRun raised = run_cli({"check", model.string(), "--max-depth", "70"}, folder_);
  EXPECT_EQ(raised.exit_code, exit_success) << raised.err;
  const CliRun solved = run_cli({"solve", model.string(), "--max-depth", "100"}, folder_);
  EXPECT_EQ(solved.exit_code, exit_success) << solved.err;

  LoadLimits limits;
  limits.max_nesting_depth = 70;
  EXPECT_EQ(load_model(model, limits).name, "cantilever");
  limits.max_nesting_depth = 69;
  EXPECT_THROW(load_model(model, limits), InputError);
}

TEST_F(Limits, TooManyEntitiesAreRefusedAndTheOptionRaisesTheLimit) {
  // Two points; one of every other kind.
  const fs::path model = write("rod.yaml", cantilever_model);
  const fs::path result = folder_ / "result.json";

  const CliRun run =
      run_cli({"solve", model.string(), "--max-entities", "1", "--json", result.string()}, folder_);
  EXPECT_TRUE(refused(run));
  EXPECT_FALSE(fs::exists(result));
  const auto lines = lines_of(run.err);
  ASSERT_EQ(lines.size(), 1u) << run.err;
  EXPECT_EQ(lines[0].rfind(std::string(error_prefix) + model.string() +
                               ":3:1: points: the model has 2 points, above the limit of 1 of "
                               "each kind",
                           0),
            0u)
      << run.err;
  EXPECT_TRUE(contains(lines[0], "--max-entities")) << run.err;

  const CliRun check = run_cli({"check", model.string(), "--max-entities", "1"}, folder_);
  EXPECT_TRUE(refused(check));
  const CliRun raised = run_cli({"check", model.string(), "--max-entities", "2"}, folder_);
  EXPECT_EQ(raised.exit_code, exit_success) << raised.err;

  LoadLimits limits;
  limits.max_entities = 1;
  const Diagnostic d = refusal_of(cantilever_model, limits);
  EXPECT_EQ(d.key_path, "points");
  EXPECT_TRUE(contains(d.message, "LoadLimits::max_entities")) << d.message;
  limits.max_entities = 2;
  EXPECT_EQ(parse_model(cantilever_model, "rod.yaml", limits).points.size(), 2u);
}

TEST_F(Limits, BadLimitOptionsAreRefused) {
  const fs::path model = write("rod.yaml", cantilever_model);
  for (const auto& [option, value] :
       std::vector<std::pair<std::string, std::string>>{{"--max-file-size", "0"},
                                                        {"--max-file-size", "lots"},
                                                        {"--max-depth", "0"},
                                                        {"--max-entities", "-5"}}) {
    const CliRun run = run_cli({"check", model.string(), option, value}, folder_);
    EXPECT_TRUE(refused(run)) << option << " " << value;
    EXPECT_TRUE(contains(run.err, option)) << run.err;
  }
}

// ---- a large model -------------------------------------------------------------------------

TEST_F(Limits, ChainOf100000LinksLoadsQuickly) {
  // Beams between points 1 cm apart, elastic joints between them, clamped at P0.
  constexpr int links = 100'000;
  const fs::path chain = folder_ / "chain.yaml";
  {
    std::ofstream out(chain);
    out << "format: stiffmsa/1\nname: chain\nmaterials:\n  steel: {E: 2.1e11, nu: 0.3}\n"
           "sections:\n  rod: {shape: circle, D: 0.05}\npoints:\n";
    for (int i = 0; i <= links; ++i) out << "  P" << i << ": [" << i << "e-2, 0, 0]\n";
    out << "links:\n";
    for (int i = 0; i < links; ++i)
      out << "  L" << i << ": {type: beam, from: P" << i << ", to: P" << i + 1
          << ", material: steel, section: rod}\n";
    out << "joints:\n";
    for (int i = 1; i < links; ++i)
      out << "  J" << i << ": {type: revolute, at: P" << i << ", links: [L" << i - 1 << ", L" << i
          << "], axis: [0, 0, 1], stiffness: 1.0e5}\n";
    out << "supports:\n  clamp: {type: rigid, at: P0}\nloads:\n  - {at: P" << links
        << ", wrench: [0, -1, 0, 0, 0, 0]}\nend_effectors:\n  tip: {at: P" << links << "}\n";
  }
  EXPECT_LT(fs::file_size(chain), LoadLimits{}.max_file_bytes / 2);

  // Processor time, not wall time: other processes on the machine do not count. Loading
  // takes a few seconds; a scan per key or name would take minutes.
  const std::clock_t start = std::clock();
  const Model model = load_model(chain);
  const double seconds = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
  RecordProperty("load_seconds", std::to_string(seconds));
  std::cout << "100 000-link chain (" << fs::file_size(chain) << " bytes) loaded in " << seconds
            << " s of processor time\n";
  EXPECT_LT(seconds, 40.0);

  ASSERT_EQ(model.links.size(), static_cast<std::size_t>(links));
  EXPECT_EQ(model.points.size(), static_cast<std::size_t>(links + 1));
  EXPECT_EQ(model.joints.size(), static_cast<std::size_t>(links - 1));
  EXPECT_EQ(model.points.back().position.x(), 1000.0);
  EXPECT_EQ(model.links.back().from, "P99999");
  EXPECT_EQ(model.joints.back().links, (std::vector<std::string>{"L99998", "L99999"}));
}

// ---- options ---------------------------------------------------------------------------------

TEST(ModelOptions, AcceptIdleMotionsIsReadFromTheFile) {
  const std::string model = cantilever_model;
  EXPECT_FALSE(parse_model(model, "rod.yaml").options.accept_idle_motions);
  EXPECT_TRUE(parse_model(model + "options: {accept_idle_motions: true}\n", "rod.yaml")
                  .options.accept_idle_motions);
  EXPECT_FALSE(
      parse_model(model + "options:\n  accept_idle_motions: false\n  x-why: a note\n", "rod.yaml")
          .options.accept_idle_motions);
  EXPECT_FALSE(parse_model(model + "options:\n", "rod.yaml").options.accept_idle_motions);
}

TEST(ModelOptions, OptionsMustBeAMapping) {
  try {
    parse_model(std::string(cantilever_model) + "options: [accept_idle_motions]\n", "rod.yaml");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    ASSERT_EQ(e.diagnostics().size(), 1u) << e.what();
    EXPECT_EQ(e.diagnostics()[0].key_path, "options");
    // The line after the rod's, where `options:` was appended.
    const auto rod_lines =
        std::count(cantilever_model, cantilever_model + std::strlen(cantilever_model), '\n');
    EXPECT_EQ(e.diagnostics()[0].location.line, rod_lines + 1);
    EXPECT_TRUE(contains(e.diagnostics()[0].message, "expected a mapping")) << e.what();
  }
}

using CommandOptions = TempFolder;

TEST_F(CommandOptions, AcceptIdleMotionsIsAnOptionOfSolve) {
  const fs::path model = write("rod.yaml", cantilever_model);
  const CliRun run = run_cli({"solve", model.string(), "--accept-idle-motions"}, folder_);
  EXPECT_EQ(run.exit_code, exit_success) << run.err;
  EXPECT_TRUE(contains(run.out, "Model: cantilever")) << run.out;
  const CliRun help = run_cli({"solve", "--help"}, folder_);
  for (const char* option :
       {"--accept-idle-motions", "--max-file-size", "--max-depth", "--max-entities"})
    EXPECT_TRUE(contains(help.out, option)) << help.out;
}

}  // namespace
}  // namespace stiffmsa
