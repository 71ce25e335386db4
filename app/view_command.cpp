#include "view_command.hpp"

#include <cstdio>
#include <iostream>

#include "summary.hpp"
#include "sweep_command.hpp"

namespace stiffmsa::cli {

namespace fs = std::filesystem;

namespace {

// "x = 0.1 m" per parameter of a parametric model, at the values the page shows.
std::vector<std::string> parameter_texts(const ModelFamily& family,
                                         const std::vector<double>& values) {
  std::vector<std::string> texts;
  for (std::size_t k = 0; k < family.parameters().size(); ++k) {
    const Parameter& parameter = family.parameters()[k];
    char number[32];
    std::snprintf(number, sizeof number, "%.6g", values[k]);
    texts.push_back(parameter.name + " = " + number +
                    (parameter.unit.empty() ? "" : " " + parameter.unit));
  }
  return texts;
}

// The model as the page shows it: with the loads of the case whose results it draws (`name`, or
// where the model's own loads are no case, its first named case's).
Model with_case_loads(const Model& model, const std::string& name) {
  const LoadCase* shown = nullptr;
  if (!name.empty()) {
    std::string cases;
    for (const LoadCase& c : model.load_cases) {
      if (c.name == name) shown = &c;
      cases += (cases.empty() ? "'" : ", '") + c.name + "'";
    }
    if (!shown)
      throw UsageError(
          "--case '" + name + "': the model has no load case of that name (" +
          (cases.empty() ? std::string("it names no load case") : "its cases: " + cases) + ")");
  } else if (model.loads.empty() && model.link_loads.empty() && !model.gravity &&
             !model.load_cases.empty()) {
    shown = &model.load_cases.front();
  }
  Model drawn = model;
  if (shown) {
    drawn.loads = shown->loads;
    drawn.link_loads = shown->link_loads;
    drawn.gravity = shown->gravity;
  }
  return drawn;
}

}  // namespace

CLI::App* add_view_subcommand(CLI::App& app, ViewCommand& command) {
  CLI::App* view = app.add_subcommand(
      "view",
      "Write an HTML page that shows the model in 3-D with its deformed shape and ellipsoids");
  view->add_option("MODEL", command.model_file, "Model file (YAML or JSON)")->required();
  view->add_option("-o,--output", command.html_file,
                   "The page to write (default: MODEL with .html)");
  view->add_option("--scale", command.scale,
                   "Magnification of the deformed shape (default: the largest displacement drawn "
                   "as a tenth of "
                   "the model); the page has a slider too")
      ->check(CLI::Validator(
          [](std::string& input) -> std::string {
            const auto value = parse_plain_number(input);
            return value && *value > 0 ? std::string()
                                       : "expected a positive number, got '" + input + "'";
          },
          "S > 0"));
  view->add_option("--case", command.load_case,
                   "The named load case whose deformed shape and loads are shown (default: the "
                   "top-level results: the unnamed case, else the first named one)");
  view->add_option("--set", command.settings,
                   "Parametric models: a parameter's value, NAME=VALUE (repeatable)");
  return view;
}

int run_view(const ViewCommand& command) {
  fs::path html_file = command.html_file;
  if (html_file.empty()) html_file = fs::path(command.model_file).replace_extension(".html");
  if (same_file(command.model_file, html_file))
    throw UsageError("the page '" + html_file.string() +
                     "' is the model file; choose another name with -o");

  const ModelFamily family =
      load_model_family(command.model_file, command.limits, parse_settings(command.settings));
  const std::vector<double> values = family.default_values();
  const Model model = family.build(values);

  ModelViewOptions options;
  options.scale = command.scale;
  options.parameters = parameter_texts(family, values);
  // A model that cannot be solved is still worth seeing: a mechanism often shows why.
  const Model drawn = with_case_loads(model, command.load_case);
  std::optional<Result> result;
  int code = exit_success;
  try {
    result = solve(model, command.solve);
    if (!command.load_case.empty()) result = Result(result->load_case_result(command.load_case));
  } catch (const SingularModelError& e) {
    options.not_solved = e.what();
    print_singular_model_error(std::cerr, e);
    code = exit_cannot_solve;
  }
  write_model_view(drawn, result ? &*result : nullptr, options, html_file);
  std::cout << "View of " << model.name << " written to " << html_file.string() << '\n';
  return code;
}

}  // namespace stiffmsa::cli
