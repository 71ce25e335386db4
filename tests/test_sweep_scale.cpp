// Sweeps beyond one process: blocks, shards joined by `stiffmsa merge`, HDF5 rows and MPI ranks
// all give the rows and summary of one run, byte for byte; parts of another sweep are refused
// and a rank that dies ends the run.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "stiffmsa/io/model_file.hpp"
#include "stiffmsa/io/sweep_file.hpp"
#include "stiffmsa/sweep.hpp"

namespace stiffmsa {
namespace {

namespace fs = std::filesystem;
using stiffmsa::testing::contains;
using stiffmsa::testing::read_file;
using stiffmsa::testing::shell_quoted;

std::string example(const std::string& name) {
  return std::string(STIFFMSA_SOURCE_DIR) + "/examples/" + name;
}

// The summary without what depends on how the sweep ran (and on the rows file's name).
nlohmann::json run_independent(const fs::path& summary_file) {
  auto summary = nlohmann::json::parse(read_file(summary_file));
  for (const char* key : {"threads", "seconds", "csv", "hdf5", "ranks"}) summary.erase(key);
  return summary;
}

struct CommandRun {
  int exit_code = -1;
  std::string out, err;
};

class SweepScale : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() /
              ("stiffmsa-test-scale-" + std::to_string(::getpid()) + "-" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  // Runs a shell command line (the program's path is `$S`); no stdin.
  CommandRun shell(const std::string& line, const std::string& environment = "") const {
    const fs::path out = folder_ / "stdout.txt", err = folder_ / "stderr.txt";
    const std::string command = "cd " + shell_quoted(folder_.string()) + " && " + environment +
                                " S=" + shell_quoted(STIFFMSA_CLI) + "; " + line + " >" +
                                shell_quoted(out.string()) + " 2>" + shell_quoted(err.string()) +
                                " </dev/null";
    const int status = std::system(command.c_str());
    CommandRun run;
    if (status != -1 && WIFEXITED(status)) run.exit_code = WEXITSTATUS(status);
    run.out = read_file(out);
    run.err = read_file(err);
    return run;
  }
  CommandRun cli(const std::string& arguments) const { return shell("\"$S\" " + arguments); }

  // The rows and summary of one plain run.
  void whole_run(const std::string& sweep, const std::string& name) const {
    const CommandRun r = cli("sweep " + sweep + " --quiet --csv " + name);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }

  fs::path folder_;
};

// 3-RPR over 41 × 39 poses: its map falls by decades onto the parallel singularity.
const std::string three_rpr = shell_quoted(example("planar-3rpr-parametric.yaml")) +
                              " --grid x=0.1:0.9:41 --grid y=0.05:0.8:39";
// Tripteron over 17 × 15 poses, some out of reach: failed poses in every part.
const std::string tripteron = shell_quoted(example("tripteron-parametric.yaml")) +
                              " --grid px=0.1:0.75:17 --grid py=0.1:0.4:15 --full";

// ---- blocks and the summary ---------------------------------------------------------------

TEST(SweepBlocks, SummariesOfBlocksAddUpToTheWholeInAnyOrder) {
  const ModelFamily family = load_model_family(example("tripteron-parametric.yaml"));
  const SweepResult whole = sweep(family, grid_poses({{"px", 0.1, 0.75, 17}, {"py", 0.1, 0.4, 15}}),
                                  SweepOptions{{}, true, 2, {}});
  ASSERT_GT(whole.results.size(), 200u);
  const auto columns = sweep_columns(whole, true);
  const SweepRows rows = sweep_rows(whole, columns);
  ASSERT_GT(rows.size() - static_cast<std::size_t>(std::count(rows.statuses.begin(),
                                                              rows.statuses.end(), PoseStatus::ok)),
            10u)
      << "the grid must reach out of the workspace";

  // Blocks of 7 rows, summarised alone, passed through bytes and added last block first.
  SweepSummary added(columns);
  for (std::size_t first = rows.size() - rows.size() % 7;; first -= 7) {
    const std::size_t count = std::min<std::size_t>(7, rows.size() - first);
    SweepResult part = whole;
    part.results.assign(whole.results.begin() + static_cast<std::ptrdiff_t>(first),
                        whole.results.begin() + static_cast<std::ptrdiff_t>(first + count));
    part.poses.values.assign(
        whole.poses.values.begin() + static_cast<std::ptrdiff_t>(2 * first),
        whole.poses.values.begin() + static_cast<std::ptrdiff_t>(2 * (first + count)));
    std::string bytes;
    serialize_rows(bytes, sweep_rows(part, columns, first));
    const SweepRows block = deserialize_rows(bytes);
    EXPECT_EQ(block.first_pose, first);
    SweepSummary one(columns);
    one.add(block);
    added.add(SweepSummary::deserialize(columns, one.serialize()));
    if (first == 0) break;
  }
  EXPECT_EQ(added.poses(), whole.results.size());
  EXPECT_EQ(sweep_summary_to_json(whole, true, added, "rows.csv"),
            sweep_summary_to_json(whole, true, "rows.csv"));
  ASSERT_TRUE(added.first_failed().has_value());
  for (std::size_t pose = 0; pose < whole.results.size(); ++pose)
    if (whole.results[pose].status != PoseStatus::ok) {
      EXPECT_EQ(added.first_failed()->index, pose);
      EXPECT_EQ(added.first_failed()->message, whole.results[pose].message);
      break;
    }
}

TEST_F(SweepScale, TheCsvReadsBackToTheSameRows) {
  const ModelFamily family = load_model_family(example("tripteron-parametric.yaml"));
  const SweepResult whole = sweep(family, grid_poses({{"px", 0.1, 0.75, 9}, {"py", 0.1, 0.4, 7}}),
                                  SweepOptions{{}, true, 1, {}});
  const auto columns = sweep_columns(whole, true);
  std::ofstream(folder_ / "rows.csv") << sweep_to_csv(whole, true);
  SweepCsvReader reader(folder_ / "rows.csv", whole.poses.parameters, columns);
  const SweepRows expected = sweep_rows(whole, columns);
  const SweepRows first = reader.read(0, 40), rest = reader.read(40, 1000);
  ASSERT_EQ(first.size() + rest.size(), expected.size());
  for (std::size_t row = 0; row < expected.size(); ++row) {
    const SweepRows& read = row < 40 ? first : rest;
    const std::size_t at = row < 40 ? row : row - 40;
    EXPECT_EQ(read.statuses[at], expected.statuses[row]);
    EXPECT_EQ(read.messages[at], expected.messages[row]);
    for (std::size_t c = 0; c < columns.size(); ++c) {
      const double a = read.value(at, c), b = expected.value(row, c);
      EXPECT_TRUE(a == b || (std::isnan(a) && std::isnan(b)))
          << "row " << row << " " << columns[c].name;
    }
  }
  EXPECT_EQ(reader.read(expected.size(), 10).size(), 0u);
}

TEST_F(SweepScale, BlockSizeAndThreadsDoNotChangeTheFiles) {
  whole_run(tripteron + " --threads 2", "whole.csv");
  for (const char* options :
       {" --block 1 --threads 1", " --block 7", " --block 100000 --threads 1"}) {
    const CommandRun r = cli("sweep " + tripteron + options + " --quiet --csv blocks.csv");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(read_file(folder_ / "blocks.csv"), read_file(folder_ / "whole.csv")) << options;
    EXPECT_EQ(run_independent(folder_ / "blocks.summary.json"),
              run_independent(folder_ / "whole.summary.json"))
        << options;
  }
}

// ---- shards ----------------------------------------------------------------------------------

TEST_F(SweepScale, ShardsMergedEqualTheWholeRun) {
  for (const std::string& sweep : {three_rpr, tripteron}) {
    whole_run(sweep + " --plot", "whole.csv");
    // 4 parts of 1 599 or 255 poses: unequal parts, solved with other blocks and threads.
    for (int k = 1; k <= 4; ++k) {
      const CommandRun r =
          cli("sweep " + sweep + " --quiet --shard " + std::to_string(k) + "/4 --block " +
              std::to_string(10 + 13 * k) + " --threads " + std::to_string(1 + k % 2) +
              " --csv part" + std::to_string(k) + ".csv");
      ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    const auto part2 = nlohmann::json::parse(read_file(folder_ / "part2.summary.json"));
    EXPECT_EQ(part2["shard"]["part"], 2);
    EXPECT_EQ(part2["shard"]["parts"], 4);
    const std::size_t all = part2["shard"]["poses_in_all"];
    EXPECT_EQ(part2["shard"]["first_pose"], all / 4);
    EXPECT_EQ(part2["poses"], all / 2 - all / 4);

    const CommandRun merged =
        cli("merge merged.csv part3.csv part1.csv part4.csv part2.csv --plot");
    ASSERT_EQ(merged.exit_code, 0) << merged.err;
    EXPECT_EQ(read_file(folder_ / "merged.csv"), read_file(folder_ / "whole.csv"));
    EXPECT_EQ(run_independent(folder_ / "merged.summary.json"),
              run_independent(folder_ / "whole.summary.json"));
    for (const char* plot : {".platform.k_trans_min.png", ".platform.deflection_trans.svg"}) {
      EXPECT_GT(fs::file_size(folder_ / ("merged" + std::string(plot))), 1000u);
      EXPECT_EQ(read_file(folder_ / ("merged" + std::string(plot))),
                read_file(folder_ / ("whole" + std::string(plot))))
          << plot;
    }
    EXPECT_TRUE(contains(merged.out, std::to_string(all) + " poses")) << merged.out;
  }
}

TEST_F(SweepScale, MergeRefusesPartsOfAnotherSweep) {
  const std::string base =
      shell_quoted(example("planar-3rpr-parametric.yaml")) + " --quiet --grid x=0.1:0.9:5";
  for (const char* part : {"1", "2", "3"})
    ASSERT_EQ(
        cli("sweep " + base + " --grid y=0.1:0.5:4 --shard " + part + "/3 --csv p" + part + ".csv")
            .exit_code,
        0);
  ASSERT_EQ(cli("sweep " + base + " --grid y=0.1:0.5:5 --shard 2/3 --csv grid.csv").exit_code, 0);
  ASSERT_EQ(
      cli("sweep " + base + " --grid y=0.1:0.5:4 --set k_actuator=3e7 --shard 2/3 --csv set.csv")
          .exit_code,
      0);
  ASSERT_EQ(
      cli("sweep " + base + " --grid y=0.1:0.5:4 --full --shard 2/3 --csv full.csv").exit_code, 0);
  ASSERT_EQ(cli("sweep " + base + " --grid y=0.1:0.5:4 --shard 2/4 --csv four.csv").exit_code, 0);
  ASSERT_EQ(cli("sweep " + base + " --grid y=0.1:0.5:4 --csv plain.csv").exit_code, 0);
  fs::copy_file(folder_ / "p3.csv", folder_ / "short.csv");
  fs::copy_file(folder_ / "p3.summary.json", folder_ / "short.summary.json");
  const std::string rows = read_file(folder_ / "p3.csv");
  std::ofstream(folder_ / "short.csv") << rows.substr(0, rows.rfind('\n', rows.size() - 2) + 1);
  struct Case {
    std::string parts, expected;
  };
  for (const Case& c : std::vector<Case>{
           {"p1.csv grid.csv p3.csv", "another grid"},
           {"p1.csv set.csv p3.csv", "other --set values"},
           {"p1.csv full.csv p3.csv", "--full in one"},
           {"p1.csv four.csv p3.csv", "of 4"},
           {"p1.csv p3.csv", "parts 2 of 3 are missing"},
           {"p1.csv p2.csv p2.csv p3.csv", "given twice"},
           {"p1.csv p2.csv plain.csv", "not a part of a sharded sweep"},
           {"p1.csv p2.csv short.csv", "where its summary counts"},
           {"p1.csv p2.csv nothing.csv", "cannot read"},
       }) {
    const CommandRun r = cli("merge out.csv " + c.parts);
    EXPECT_NE(r.exit_code, 0) << c.parts;
    EXPECT_TRUE(contains(r.err, c.expected)) << c.parts << ": " << r.err;
    EXPECT_FALSE(fs::exists(folder_ / "out.csv")) << c.parts;
    EXPECT_FALSE(fs::exists(folder_ / "out.summary.json")) << c.parts;
  }
  // The model file itself changed between parts.
  const std::string model = read_file(example("planar-3rpr-parametric.yaml"));
  std::ofstream(folder_ / "model.yaml") << model;
  ASSERT_EQ(
      cli("sweep model.yaml --quiet --grid x=0.1:0.9:5 --grid y=0.1:0.5:4 --shard 1/2 --csv m1.csv")
          .exit_code,
      0);
  std::ofstream(folder_ / "model.yaml") << model << "# edited\n";
  ASSERT_EQ(
      cli("sweep model.yaml --quiet --grid x=0.1:0.9:5 --grid y=0.1:0.5:4 --shard 2/2 --csv m2.csv")
          .exit_code,
      0);
  const CommandRun r = cli("merge out.csv m1.csv m2.csv");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(contains(r.err, "another model file")) << r.err;
}

TEST_F(SweepScale, ShardOptionsAreChecked) {
  for (const char* shard : {"0/3", "4/3", "3", "1/0", "a/b"}) {
    const CommandRun r = cli("sweep " + three_rpr + " --shard " + shard + " --csv x.csv");
    EXPECT_EQ(r.exit_code, 2) << shard;
    EXPECT_TRUE(contains(r.err, "K/N")) << shard << ": " << r.err;
  }
  const CommandRun plot = cli("sweep " + three_rpr + " --shard 1/2 --plot --csv x.csv");
  EXPECT_EQ(plot.exit_code, 2);
  EXPECT_TRUE(contains(plot.err, "when merging")) << plot.err;
  EXPECT_FALSE(fs::exists(folder_ / "x.csv"));
}

// ---- HDF5 ------------------------------------------------------------------------------------

// h5py reads every column of the HDF5 file as the CSV has it, the statuses by name, the units
// and the summary; pandas makes a table of them.
constexpr const char* check_hdf5_script = R"(
import json, sys, h5py, numpy, pandas
f = h5py.File(sys.argv[1], "r")
csv = pandas.read_csv(sys.argv[2], float_precision="round_trip", keep_default_na=False, dtype=str)
names = [n.decode() if isinstance(n, bytes) else n for n in f.attrs["columns"]]
assert names == list(csv.columns), (names, list(csv.columns))
table = pandas.DataFrame({n: f[n][()] for n in names})
assert len(table) == len(csv)
codes = h5py.check_enum_dtype(f["status"].dtype)
by_code = {v: k for k, v in codes.items()}
assert [by_code[c] for c in table["status"]] == list(csv["status"])
assert [m.decode() if isinstance(m, bytes) else m for m in table["message"]] == list(csv["message"])
for n in names:
    if n in ("status", "message"):
        continue
    expected = numpy.array([float(v) if v != "" else numpy.nan for v in csv[n]])
    assert numpy.array_equal(table[n].to_numpy(), expected, equal_nan=True), n
summary = json.loads(f.attrs["summary"])
assert summary == json.load(open(sys.argv[3])), "summary"
assert int(f.attrs["poses"]) == len(csv) and int(f.attrs["status.ok"]) == summary["status"]["ok"]
assert f["x" if "x" in f else "px"].attrs["unit"] == "m"
print("checked", len(csv), "rows")
)";

TEST_F(SweepScale, Hdf5HoldsTheRowsOfTheCsv) {
#if !STIFFMSA_TEST_HDF5
  const CommandRun refused = cli("sweep " + tripteron + " --quiet --hdf5 rows.h5");
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_TRUE(contains(refused.err, "built without HDF5")) << refused.err;
  EXPECT_FALSE(fs::exists(folder_ / "rows.h5"));
  GTEST_SKIP() << "built without HDF5: --hdf5 is refused";
#endif
  if (shell("/usr/bin/python3 -c 'import h5py, pandas'").exit_code != 0)
    GTEST_SKIP()
        << "no /usr/bin/python3 with h5py and pandas (scripts/install-deps.sh installs them)";
  std::ofstream(folder_ / "check.py") << check_hdf5_script;
  const CommandRun r =
      cli("sweep " + tripteron + " --quiet --block 50 --csv rows.csv --hdf5 rows.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const CommandRun check = shell("/usr/bin/python3 check.py rows.h5 rows.csv rows.summary.json");
  EXPECT_EQ(check.exit_code, 0) << check.err;
  EXPECT_TRUE(contains(check.out, "checked 255 rows")) << check.out << check.err;

  // HDF5 alone, and a merge into HDF5, hold the same.
  ASSERT_EQ(cli("sweep " + tripteron + " --quiet --hdf5 only.h5").exit_code, 0);
  for (const char* k : {"1", "2"})
    ASSERT_EQ(
        cli("sweep " + tripteron + " --quiet --shard " + std::string(k) + "/2 --csv p" + k + ".csv")
            .exit_code,
        0);
  ASSERT_EQ(cli("merge merged.h5 p1.csv p2.csv").exit_code, 0);
  for (const char* file : {"only", "merged"}) {
    const CommandRun again = shell("/usr/bin/python3 check.py " + std::string(file) +
                                   ".h5 rows.csv " + file + ".summary.json");
    EXPECT_EQ(again.exit_code, 0) << file << again.err;
  }
  EXPECT_EQ(run_independent(folder_ / "merged.summary.json"),
            run_independent(folder_ / "rows.summary.json"));

  // HDF5 parts (shards written with --hdf5) merge as CSV parts do, alone or mixed with CSV parts,
  // into HDF5 or CSV; a part whose summary file is gone merges by the summary the HDF5 file holds.
  for (const char* k : {"1", "2", "3"})
    ASSERT_EQ(cli("sweep " + tripteron + " --quiet --shard " + std::string(k) +
                  "/3 --block 40 --hdf5 h" + k + ".h5")
                  .exit_code,
              0);
  ASSERT_EQ(cli("sweep " + tripteron + " --quiet --shard 2/3 --csv c2.csv").exit_code, 0);
  fs::remove(folder_ / "h3.summary.json");
  for (const std::string parts : {"h3.h5 h1.h5 h2.h5", "h1.h5 c2.csv h3.h5"})
    for (const char* out : {"joined.h5", "joined.csv"}) {
      const CommandRun joined = cli("merge " + std::string(out) + " " + parts);
      ASSERT_EQ(joined.exit_code, 0) << parts << " " << out << joined.err;
      if (std::string(out).ends_with(".csv")) {
        EXPECT_EQ(read_file(folder_ / out), read_file(folder_ / "rows.csv")) << parts;
      } else {
        const CommandRun again =
            shell("/usr/bin/python3 check.py joined.h5 rows.csv joined.summary.json");
        EXPECT_EQ(again.exit_code, 0) << parts << again.err;
      }
      EXPECT_EQ(run_independent(folder_ / "joined.summary.json"),
                run_independent(folder_ / "rows.summary.json"))
          << parts;
      fs::remove(folder_ / out);
    }

  // HDF5 parts of another sweep, and files that are not a sweep's HDF5 rows, are refused.
  ASSERT_EQ(cli("sweep " + tripteron + " --quiet --shard 2/4 --hdf5 four.h5").exit_code, 0);
  ASSERT_EQ(
      cli("sweep " + shell_quoted(example("tripteron-parametric.yaml")) +
          " --grid px=0.1:0.75:16 --grid py=0.1:0.4:15 --full --quiet --shard 2/3 --hdf5 grid.h5")
          .exit_code,
      0);
  fs::copy_file(folder_ / "h2.summary.json", folder_ / "text.summary.json");
  std::ofstream(folder_ / "text.h5") << "not HDF5\n";
  ASSERT_EQ(shell("/usr/bin/python3 -c 'import h5py, shutil; shutil.copy(\"h2.h5\", \"cut.h5\"); "
                  "f = h5py.File(\"cut.h5\", \"r+\"); f[\"status\"].resize((10,)); f.close()'")
                .exit_code,
            0);
  fs::copy_file(folder_ / "h2.summary.json", folder_ / "cut.summary.json");
  struct Case {
    std::string parts, expected;
  };
  for (const Case& c : std::vector<Case>{{"h1.h5 four.h5 h3.h5", "of 4"},
                                         {"h1.h5 grid.h5 h3.h5", "another grid"},
                                         {"h1.h5 text.h5 h3.h5", "not an HDF5 file"},
                                         {"h1.h5 cut.h5 h3.h5", "has 10 rows where the first has"},
                                         {"h1.h5 h3.h5", "parts 2 of 3 are missing"}}) {
    const CommandRun r = cli("merge out.h5 " + c.parts);
    EXPECT_NE(r.exit_code, 0) << c.parts;
    EXPECT_TRUE(contains(r.err, c.expected)) << c.parts << ": " << r.err;
    EXPECT_FALSE(fs::exists(folder_ / "out.h5")) << c.parts;
    EXPECT_FALSE(fs::exists(folder_ / "out.summary.json")) << c.parts;
  }
}

// ---- MPI -------------------------------------------------------------------------------------

// mpirun as root needs these; set for the test's commands only. --oversubscribe: more ranks than
// the machine's cores (3 on this 2-core machine; 2 on a 1-core CI runner).
const std::string mpirun =
    "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 timeout 300 " +
    shell_quoted(STIFFMSA_TEST_MPIEXEC) + " --oversubscribe";

// Issue 18's additions through shards, merge and MPI ranks: 10 of these 20 poses near the
// singularity deflect beyond the linear range; the fixed parameters, direction columns, count,
// first such pose, plot subtitles and rings are those of the run in one process.
TEST_F(SweepScale, LargeDeflectionsAndFixedParametersSurviveShardsMergeAndRanks) {
  const std::string sweep =
      shell_quoted(example("planar-3rpr-parametric.yaml")) +
      " --grid x=0.3:0.34:5 --grid y=0.74:0.7605:4 --threads 1 --direction 1,0,0";
  const CommandRun whole = cli("sweep " + sweep + " --quiet --plot --view --csv whole.csv");
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  const auto summary = nlohmann::json::parse(read_file(folder_ / "whole.summary.json"));
  ASSERT_EQ(summary["large_deflection"], 10);
  EXPECT_EQ(summary["fixed_parameters"]["r"]["value"], 0.12);
  EXPECT_TRUE(fs::file_size(folder_ / "whole.html") > 1000u);
  const std::string first_large =
      "  first pose with large deflections (x = 0.3 m, y = 0.7468333333333333 m): "
      "the deflections under the loads are too large for the linear method";
  EXPECT_TRUE(contains(whole.out, "  at phi = 0.0831 rad, r = 0.12 m, k_actuator = 1.5e+07 N/m\n"))
      << whole.out;
  EXPECT_TRUE(contains(whole.out, "status: ok 20 (10 with large deflections)\n")) << whole.out;
  EXPECT_TRUE(contains(whole.out, first_large)) << whole.out;

  for (int k = 1; k <= 3; ++k)
    ASSERT_EQ(cli("sweep " + sweep + " --quiet --block 2 --shard " + std::to_string(k) +
                  "/3 --csv part" + std::to_string(k) + ".csv")
                  .exit_code,
              0);
  const CommandRun merged = cli("merge merged.csv part2.csv part3.csv part1.csv --plot");
  ASSERT_EQ(merged.exit_code, 0) << merged.err;
  std::vector<std::string> outputs{"merged"};
  std::vector<CommandRun> runs{merged};
#if STIFFMSA_TEST_MPI
  runs.push_back(
      shell(mpirun + " -n 2 \"$S\" sweep " + sweep + " --block 3 --quiet --plot --csv ranks.csv"));
  ASSERT_EQ(runs.back().exit_code, 0) << runs.back().err;
  outputs.push_back("ranks");
#endif
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const std::string& name = outputs[i];
    EXPECT_EQ(read_file(folder_ / (name + ".csv")), read_file(folder_ / "whole.csv")) << name;
    EXPECT_EQ(run_independent(folder_ / (name + ".summary.json")),
              run_independent(folder_ / "whole.summary.json"))
        << name;
    for (const char* plot : {".platform.k_trans_min.png", ".platform.deflection_trans.svg"})
      EXPECT_EQ(read_file(folder_ / (name + plot)),
                read_file(folder_ / ("whole" + std::string(plot))))
          << name << plot;
    EXPECT_TRUE(contains(runs[i].out, "status: ok 20 (10 with large deflections)\n"))
        << runs[i].out;
    EXPECT_TRUE(contains(runs[i].out, first_large)) << runs[i].out;
    EXPECT_TRUE(
        contains(runs[i].out, "  at phi = 0.0831 rad, r = 0.12 m, k_actuator = 1.5e+07 N/m\n"))
        << runs[i].out;
  }
  EXPECT_NE(cli("sweep " + sweep + " --quiet --view --shard 1/3 --csv v.csv").exit_code, 0);
}

TEST_F(SweepScale, RanksWriteTheRowsOfOneProcess) {
#if !STIFFMSA_TEST_MPI
  GTEST_SKIP() << "built without MPI (STIFFMSA_WITH_MPI=OFF)";
#endif
  for (const std::string& sweep : {three_rpr, tripteron}) {
    whole_run(sweep + " --threads 1", "one.csv");
    struct Case {
      std::string ranks, options;
    };
    // 2 ranks; 3 ranks on 2 cores with blocks that do not divide the poses; ranks of a shard.
    for (const Case& c : std::vector<Case>{{"-n 2", " --block 64"},
                                           {"-n 3", " --block 37"},
                                           {"-n 2", " --block 29 --threads 1"}}) {
      const CommandRun r = shell(mpirun + " " + c.ranks + " \"$S\" sweep " + sweep + c.options +
                                 " --quiet --csv ranks.csv");
      ASSERT_EQ(r.exit_code, 0) << c.ranks << r.out << r.err;
      EXPECT_EQ(read_file(folder_ / "ranks.csv"), read_file(folder_ / "one.csv"))
          << c.ranks << c.options;
      EXPECT_EQ(run_independent(folder_ / "ranks.summary.json"),
                run_independent(folder_ / "one.summary.json"));
      EXPECT_TRUE(contains(r.out, "ranks of")) << r.out;
    }
  }
  // Shards solved by ranks merge as any others.
  whole_run(three_rpr, "whole.csv");
  for (const char* k : {"1", "2"})
    ASSERT_EQ(shell(mpirun + " -n 2 \"$S\" sweep " + three_rpr + " --quiet --block 50 --shard " +
                    k + "/2 --csv s" + k + ".csv")
                  .exit_code,
              0);
  ASSERT_EQ(cli("merge merged.csv s2.csv s1.csv").exit_code, 0);
  EXPECT_EQ(read_file(folder_ / "merged.csv"), read_file(folder_ / "whole.csv"));
}

TEST_F(SweepScale, AKilledRankEndsTheRunWithAMessage) {
#if !STIFFMSA_TEST_MPI
  GTEST_SKIP() << "built without MPI (STIFFMSA_WITH_MPI=OFF)";
#endif
  const CommandRun r =
      shell(mpirun + " -n 2 \"$S\" sweep " + three_rpr + " --quiet --block 20 --csv killed.csv",
            "export STIFFMSA_TEST_KILL_RANK=1;");
  EXPECT_NE(r.exit_code, 124) << "the run hung until `timeout` ended it";
  // mpirun exits with the status of the first process to fail, 128 + SIGKILL here, which the
  // root's own exit code (1) cannot replace (docs/cluster.md, "MPI").
  EXPECT_EQ(r.exit_code, 128 + SIGKILL) << r.out << r.err;
  EXPECT_TRUE(contains(r.err, "rank 1")) << r.err;
  EXPECT_TRUE(contains(r.err, "signal 9")) << r.err;
  EXPECT_TRUE(contains(r.err, "stiffmsa: error: the MPI job was stopped before the sweep ended"))
      << r.err;
  EXPECT_FALSE(contains(r.out, "wrote")) << r.out;
  for (const auto& entry : fs::directory_iterator(folder_))
    EXPECT_FALSE(contains(entry.path().filename().string(), "killed")) << entry.path();
}

TEST_F(SweepScale, RanksRefuseABadCommandOnce) {
#if !STIFFMSA_TEST_MPI
  GTEST_SKIP() << "built without MPI (STIFFMSA_WITH_MPI=OFF)";
#endif
  const CommandRun r =
      shell(mpirun + " -n 2 \"$S\" sweep " + shell_quoted(example("planar-3rpr-parametric.yaml")) +
            " --grid q=0:1:3 --csv bad.csv");
  EXPECT_NE(r.exit_code, 0);
  const std::string message = "no parameter 'q'";
  const auto first = r.err.find(message);
  ASSERT_NE(first, std::string::npos) << r.err;
  EXPECT_EQ(r.err.find(message, first + 1), std::string::npos)
      << "printed by every rank: " << r.err;
  EXPECT_FALSE(fs::exists(folder_ / "bad.csv"));
}

}  // namespace
}  // namespace stiffmsa
