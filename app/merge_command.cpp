#include "merge_command.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "summary.hpp"
#include "sweep_command.hpp"
#include "sweep_output.hpp"
#if STIFFMSA_CLI_HDF5
#include "stiffmsa/io/sweep_hdf5.hpp"
#endif

namespace stiffmsa::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Rows read and written at a time: memory does not grow with the parts' size.
constexpr std::size_t kRowsPerBlock = 4096;

struct Part {
  fs::path csv;  // the rows: a CSV, or an HDF5 file (.h5, .hdf5)
  fs::path summary_file;
  json summary;
  std::size_t part = 0, parts = 0, first_pose = 0, poses = 0, poses_in_all = 0;
};

fs::path summary_beside(const fs::path& rows) {
  return rows.parent_path() / (rows.stem().string() + ".summary.json");
}

bool is_hdf5_name(const fs::path& file) {
  const std::string extension = file.extension().string();
  return extension == ".h5" || extension == ".hdf5";
}

// An HDF5 part carries its summary; a copy of the part without the file beside it still merges.
std::optional<std::string> summary_inside(const fs::path& rows) {
#if STIFFMSA_CLI_HDF5
  if (is_hdf5_name(rows)) return SweepHdf5Reader::summary_of(rows);
#endif
  (void)rows;
  return std::nullopt;
}

Part read_part(const std::string& csv) {
  Part part{csv, summary_beside(csv), {}};
  std::ifstream in(part.summary_file, std::ios::binary);
  if (in) {
    part.summary = json::parse(in, nullptr, false);
  } else if (const auto inside = summary_inside(part.csv)) {
    part.summary_file = part.csv;
    part.summary = json::parse(*inside, nullptr, false);
  } else {
    throw IoError(
        "cannot read '" + part.summary_file.string() + "', the summary of the part '" + csv +
        "' (merge expects each part's summary beside it, as `stiffmsa sweep --shard` writes it)");
  }
  const json& s = part.summary;
  if (s.is_discarded() || !s.is_object() || s.value("format", "") != "stiffmsa-sweep/1")
    throw InputError({part.summary_file.string(), 0, 0}, "format",
                     "not a sweep summary (format stiffmsa-sweep/1)");
  if (!s.contains("shard") || !s.contains("identity"))
    throw InputError({part.summary_file.string(), 0, 0}, "shard",
                     "'" + csv +
                         "' is not a part of a sharded sweep; write parts with `stiffmsa sweep ... "
                         "--shard K/N`");
  try {
    const json& shard = s.at("shard");
    part.part = shard.at("part").get<std::size_t>();
    part.parts = shard.at("parts").get<std::size_t>();
    part.first_pose = shard.at("first_pose").get<std::size_t>();
    part.poses_in_all = shard.at("poses_in_all").get<std::size_t>();
    part.poses = s.at("poses").get<std::size_t>();
  } catch (const json::exception&) {
    throw InputError({part.summary_file.string(), 0, 0}, "shard",
                     "the part's number, count or poses are missing");
  }
  return part;
}

// Why two parts are not of one sweep, in the words of the sweep command's options.
std::string difference(const json& first, const json& other) {
  const std::pair<const char*, const char*> keys[] = {
      {"stiffmsa", "another version of stiffmsa"},
      {"model_file", "another model file (or another version of it)"},
      {"set", "other --set values"},
      {"grid", "another grid"},
      {"pose_file", "another pose file"},
      {"poses", "another number of poses"},
      {"full", "--full in one and not in the other"},
      {"solver", "another --solver"},
      {"direction", "another --direction"},
      {"accept_idle_motions", "--accept-idle-motions in one and not in the other"}};
  for (const auto& [key, words] : keys)
    if (first.value(key, json()) != other.value(key, json())) return words;
  return first == other ? std::string() : "another sweep";
}

// The sweep the parts describe, as its summary says it.
SweepDescription description_of(const Part& part) {
  const json& s = part.summary;
  SweepDescription description;
  try {
    description.run.model = s.at("model").get<std::string>();
    for (const auto& p : s.at("parameters")) {
      description.run.poses.parameters.push_back(p.at("name").get<std::string>());
      description.run.units.push_back(p.at("unit").get<std::string>());
      if (p.contains("grid"))
        description.run.poses.grid.push_back(
            {p["name"].get<std::string>(), p["grid"].at("start").get<double>(),
             p["grid"].at("stop").get<double>(), p["grid"].at("count").get<std::size_t>()});
    }
    description.run.end_effectors = s.at("end_effectors").get<std::vector<std::string>>();
    description.full = s.at("full").get<bool>();
    for (const auto& name : s.at("fixed_parameter_order")) {
      const json& p = s.at("fixed_parameters").at(name.get<std::string>());
      description.run.fixed_parameters.push_back(
          {name.get<std::string>(), p.at("value").get<double>(), p.at("unit").get<std::string>(),
           p.at("set").get<bool>()});
    }
    if (s.contains("direction")) {
      const auto d = s["direction"].get<std::vector<double>>();
      if (d.size() != 3)
        throw InputError({part.summary_file.string(), 0, 0}, "direction", "expected [x, y, z]");
      description.run.direction = Vec3(d[0], d[1], d[2]);
    }
    description.run.warnings = s.at("warnings").get<std::vector<std::string>>();
    description.loads = s.at("loads").get<std::string>();
  } catch (const json::exception&) {
    throw InputError({part.summary_file.string(), 0, 0}, "",
                     "the summary lacks the model, parameters, end effectors, `full`, fixed "
                     "parameters, warnings "
                     "or loads of the sweep");
  }
  description.columns = sweep_columns(description.run, description.full);
  description.poses = part.poses_in_all;
  return description;
}

// A part's rows block by block, from its CSV or its HDF5 file.
class PartRows {
 public:
  PartRows(const fs::path& file, const SweepDescription& description) {
    if (!is_hdf5_name(file)) {
      csv_.emplace(file, description.run.poses.parameters, description.columns);
      return;
    }
#if STIFFMSA_CLI_HDF5
    hdf5_.emplace(file, description.run.poses.parameters, description.columns);
#else
    throw UsageError(
        "'" + file.string() +
        "': this build of stiffmsa reads no HDF5 (built without HDF5); merge the parts' CSV files");
#endif
  }
  SweepRows read(std::size_t first_pose, std::size_t count) {
#if STIFFMSA_CLI_HDF5
    if (hdf5_) return hdf5_->read(first_pose, count);
#endif
    return csv_->read(first_pose, count);
  }
  std::size_t rows_read() const {
#if STIFFMSA_CLI_HDF5
    if (hdf5_) return hdf5_->rows_read();
#endif
    return csv_->rows_read();
  }

 private:
  std::optional<SweepCsvReader> csv_;
#if STIFFMSA_CLI_HDF5
  std::optional<SweepHdf5Reader> hdf5_;
#endif
};

}  // namespace

CLI::App* add_merge_subcommand(CLI::App& app, MergeCommand& command) {
  CLI::App* merge = app.add_subcommand(
      "merge", "Join the parts of a sweep run with --shard K/N into the files one run writes");
  merge->add_option("OUT", command.output, "The joined rows: a .csv, or .h5 / .hdf5 for HDF5")
      ->required();
  merge
      ->add_option("PARTS", command.parts,
                   "Every part's CSV or HDF5 file (its summary beside it), in any order")
      ->required();
  merge->add_option("--summary", command.summary_file,
                    "Write the JSON summary here (default: beside OUT, NAME.summary.json)");
  merge->add_flag("--plot", command.plot,
                  "Draw the maps or line plots, as `stiffmsa sweep --plot`");
  merge->add_option("--plot-column", command.plot_columns, "A column to plot (repeatable)");
  return merge;
}

int run_merge(const MergeCommand& command) {
  std::vector<Part> parts;
  for (const auto& file : command.parts) parts.push_back(read_part(file));
  const Part& first = parts.front();
  for (const Part& part : parts) {
    const std::string why = difference(first.summary["identity"], part.summary["identity"]);
    if (!why.empty())
      throw UsageError("'" + part.csv.string() + "' is a part of another sweep than '" +
                       first.csv.string() + "': " + why);
    if (part.parts != first.parts)
      throw UsageError("'" + part.csv.string() + "' is a part of " + std::to_string(part.parts) +
                       ", '" + first.csv.string() + "' of " + std::to_string(first.parts));
  }
  std::sort(parts.begin(), parts.end(),
            [](const Part& a, const Part& b) { return a.part < b.part; });
  std::string missing;
  for (std::size_t k = 1, i = 0; k <= first.parts; ++k) {
    std::size_t copies = 0;
    while (i < parts.size() && parts[i].part == k) ++copies, ++i;
    if (copies > 1)
      throw UsageError("part " + std::to_string(k) + "/" + std::to_string(first.parts) +
                       " is given twice");
    if (copies == 0) missing += (missing.empty() ? "" : ", ") + std::to_string(k);
  }
  if (!missing.empty())
    throw UsageError("parts " + missing + " of " + std::to_string(parts.front().parts) +
                     " are missing; give every part of the sweep");

  const SweepDescription description = description_of(parts.front());
  const fs::path out(command.output);
  SweepFiles files;
  (is_hdf5_name(out) ? files.hdf5 : files.csv) = out;
  files.summary =
      command.summary_file.empty() ? summary_beside(out) : fs::path(command.summary_file);
  files.plot_base = out.parent_path() / out.stem();
  for (const Part& part : parts)
    for (const fs::path& output : {out, files.summary})
      if (same_file(output, part.csv) || same_file(output, part.summary_file))
        throw UsageError("'" + output.string() +
                         "' is one of the parts' files; choose another name");
  if (command.plot) {
    std::vector<GridAxis> axes = description.run.poses.grid;
    check_plot_grid(axes, axes.size() != description.run.poses.parameters.size());
    files.plotted = plotted_columns(description.run, command.plot_columns);
  }

  SweepOutput output(description, files, 0, description.poses);
  const BlockShape shape = output.shape();
  std::size_t threads = 1;
  double seconds = 0;
  std::size_t next_pose = 0;
  for (const Part& part : parts) {
    if (part.first_pose != next_pose)
      throw UsageError("'" + part.csv.string() + "' starts at pose " +
                       std::to_string(part.first_pose) + " where the previous part ends at " +
                       std::to_string(next_pose));
    PartRows reader(part.csv, description);
    for (;;) {
      SweepRows rows = reader.read(next_pose, kRowsPerBlock);
      if (rows.size() == 0) break;
      if (reader.rows_read() > part.poses) break;
      next_pose += rows.size();
      output.write(make_block(shape, std::move(rows)));
    }
    if (reader.rows_read() != part.poses)
      throw InputError({part.csv.string(), 0, 0}, "",
                       "has " + std::to_string(reader.rows_read()) +
                           " rows where its summary counts " + std::to_string(part.poses) +
                           " (cut short, or written by another run?)");
    threads = std::max(threads, part.summary.value("threads", std::size_t{1}));
    seconds += part.summary.value("seconds", 0.0);
  }
  if (next_pose != description.poses)
    throw UsageError("the parts hold " + std::to_string(next_pose) + " poses of " +
                     std::to_string(description.poses));
  const auto written = output.finish(threads, seconds);
  print_sweep_summary(std::cout, description, output.summary(), threads, seconds, written);
  return exit_success;
}

}  // namespace stiffmsa::cli
