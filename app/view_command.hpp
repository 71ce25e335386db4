#pragma once
// `stiffmsa view`: the model, its deformed shape and its end effectors' ellipsoids as one HTML
// page (docs/viewer.md).
#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "stiffmsa/stiffmsa.hpp"

namespace stiffmsa::cli {

struct ViewCommand {
  std::string model_file;
  std::string html_file;  // empty: beside the model, MODEL.html
  std::optional<double> scale;
  std::vector<std::string> settings;  // parametric models: "name=value"
  SolveOptions solve;
  LoadLimits limits;
  std::string load_case;  // --case: the named load case whose deformed shape and loads are shown
};

// Declares the subcommand and its own options on `app` (main.cpp adds the solver and limit
// options it shares with solve), filling `command` when parsed.
CLI::App* add_view_subcommand(CLI::App& app, ViewCommand& command);

int run_view(const ViewCommand& command);

}  // namespace stiffmsa::cli
