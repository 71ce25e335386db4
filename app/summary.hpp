#pragma once
// What the stiffmsa command prints: the human-readable summary of a solve or a check, and the
// error messages. Kept apart from main.cpp so that parsing and dispatch stay short.
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "stiffmsa/stiffmsa.hpp"

namespace stiffmsa::cli {

// Exit codes of the command (README.md, "Exit codes").
enum ExitCode : int {
  exit_success = 0,
  exit_cannot_solve = 1,   // a valid model that is a mechanism or numerically singular
  exit_invalid_input = 2,  // bad model, bad usage, unreadable or unwritable files
};

// Model name, system size, every end effector's compliance, stiffness, principal stiffnesses
// and deflection, the largest joint wrench and support reaction, and the solve report.
void print_solve_summary(std::ostream& out, const Result& result,
                         const std::optional<std::filesystem::path>& result_file);

// The model's name and system size, its plausibility warnings (find_implausible_values), then
// each link's length and each joint's and support's kind and axes.
void print_check_summary(std::ostream& out, const Model& model, const SystemSize& size,
                         const std::vector<Diagnostic>& warnings);

// A parameter's value with its unit, as people read it: "0.32 m".
std::string value_with_unit(double value, const std::string& unit);

// "pz = 0.15 m (set), px = 0 m": parameters at their values, those the user set marked.
std::string parameters_text(const std::vector<ParameterValue>& parameters);

// "stiffmsa: error: <message>"
void print_error(std::ostream& err, std::string_view message);
// One line per defect.
void print_input_error(std::ostream& err, const InputError& error);
// The summary, then each detail on its own indented line.
void print_singular_model_error(std::ostream& err, const SingularModelError& error);
// Called from a catch block: prints the exception in flight as the command reports errors and
// returns its exit code.
int report_current_exception() noexcept;

}  // namespace stiffmsa::cli
