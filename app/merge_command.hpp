#pragma once
// `stiffmsa merge`: the parts of a sweep run with --shard K/N joined into the files one run
// would have written (rows, summary, plots); parts of another sweep are refused.
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace stiffmsa::cli {

struct MergeCommand {
  std::string output;              // .csv, or .h5 / .hdf5 for HDF5
  std::vector<std::string> parts;  // the parts' CSV files, each with its summary beside it
  std::string summary_file;        // empty: beside the output
  bool plot = false;
  std::vector<std::string> plot_columns;
};

// Registers the subcommand; run it with run_merge when it was parsed.
CLI::App* add_merge_subcommand(CLI::App& app, MergeCommand& command);
int run_merge(const MergeCommand& command);

}  // namespace stiffmsa::cli
