// Model families and sweeps from Python: a parametric model file's family, or one built by a
// Python function; sweeps run in the library's threads with the GIL released, and their rows
// come back as the CSV writer's columns.
#include <pybind11/functional.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <charconv>
#include <limits>
#include <memory>

#include "convert.hpp"

namespace stiffmsa::python {

namespace {

// A Python object that C++ threads may copy without the GIL: copies share one reference, and
// the last one releases it with the GIL held.
using SharedPyObject = std::shared_ptr<py::object>;
SharedPyObject share(py::object object) {
  return SharedPyObject(new py::object(std::move(object)), [](py::object* p) {
    py::gil_scoped_acquire gil;
    delete p;
  });
}

// What a Python builder function raised, kept so that a single build can raise it again as it
// was; a sweep sees only its message (the pose is invalid).
class PythonBuildError : public std::runtime_error {
 public:
  PythonBuildError(const std::string& message, std::shared_ptr<py::error_already_set> error)
      : std::runtime_error(message), error_(std::move(error)) {}
  void restore() const { error_->restore(); }

 private:
  std::shared_ptr<py::error_already_set> error_;
};

std::string call_text(const py::object& function, const py::dict& kwargs) {
  std::string text =
      py::str(py::getattr(function, "__name__", py::str("function"))).cast<std::string>() + "(";
  bool first = true;
  for (const auto& [name, value] : kwargs) {
    text += (first ? "" : ", ") + py::str(name).cast<std::string>() + "=" +
            py::repr(value).cast<std::string>();
    first = false;
  }
  return text + ")";
}

ModelFamily family_from_function(py::object function, std::vector<std::string> names,
                                 std::vector<double> defaults, std::vector<std::string> units,
                                 std::string name) {
  std::vector<Parameter> parameters;
  for (std::size_t k = 0; k < names.size(); ++k)
    parameters.push_back(Parameter{names[k], defaults[k], units[k], {}});
  const SharedPyObject shared = share(std::move(function));
  auto member = [shared, names](std::span<const double> values) -> Model {
    py::gil_scoped_acquire gil;
    py::dict kwargs;
    for (std::size_t k = 0; k < names.size(); ++k) kwargs[py::str(names[k])] = values[k];
    py::object built;
    try {
      built = (*shared)(**kwargs);
    } catch (py::error_already_set& e) {
      const std::string message = call_text(*shared, kwargs) + " raised " + e.what();
      throw PythonBuildError(message, std::make_shared<py::error_already_set>(std::move(e)));
    }
    if (!py::isinstance<Model>(built))
      throw UsageError(call_text(*shared, kwargs) + " returned " +
                       py::repr(built).cast<std::string>() + ", not a stiffmsa.Model");
    return built.cast<Model>();
  };
  return ModelFamily(std::move(name), std::move(parameters),
                     ModelFamily::MemberFunction(std::move(member)));
}

// Every parameter's value: the family's defaults, with `values` (name -> number) replacing some.
std::vector<double> member_values(const ModelFamily& family,
                                  const std::map<std::string, double>& values) {
  std::vector<double> all = family.default_values();
  for (const auto& [name, value] : values) all[family.parameter_index(name)] = value;
  return all;
}

Model build_member(const ModelFamily& family, const std::map<std::string, double>& values) {
  try {
    Model member = family.build(member_values(family, values));
    // A value the caller gives is set, as `--set` sets it on the command line.
    for (ParameterValue& p : member.parameters)
      if (values.contains(p.name)) p.set = true;
    return member;
  } catch (const PythonBuildError& e) {
    e.restore();
    throw py::error_already_set();
  }
}

// The rows of sweep_to_csv() as columns: numbers where every cell is one (NaN for an empty
// cell), text for `status`, `message` and any column holding other text. Read back from the
// writer's own text, so that they are the CSV's columns whatever columns it writes.
py::dict csv_columns(const std::string& csv) {
  std::vector<std::string> names;
  std::vector<std::vector<std::string>> cells;
  std::size_t column = 0;
  bool header = true;
  std::string field;
  const auto end_field = [&] {
    if (header) {
      names.push_back(field);
      cells.emplace_back();
    } else if (column < cells.size()) {
      cells[column].push_back(field);
    }
    ++column;
    field.clear();
  };
  // RFC 4180, as the writer quotes: a quoted field may hold commas, doubled quotes and line breaks.
  bool quoted = false;
  for (std::size_t i = 0; i < csv.size(); ++i) {
    const char c = csv[i];
    if (quoted) {
      if (c != '"')
        field += c;
      else if (i + 1 < csv.size() && csv[i + 1] == '"')
        field += csv[++i];
      else
        quoted = false;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      end_field();
    } else if (c == '\n') {
      end_field();
      header = false;
      column = 0;
    } else {
      field += c;
    }
  }
  const py::object asarray = py::module_::import("numpy").attr("asarray");
  py::dict columns;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const auto& texts = cells[k];
    py::array_t<double> numbers(static_cast<py::ssize_t>(texts.size()));
    bool numeric = names[k] != "status" && names[k] != "message";
    for (std::size_t row = 0; numeric && row < texts.size(); ++row) {
      const std::string& t = texts[row];
      double value = std::numeric_limits<double>::quiet_NaN();
      if (!t.empty()) {
        const auto [stop, error] = std::from_chars(t.data(), t.data() + t.size(), value);
        numeric = error == std::errc() && stop == t.data() + t.size();
      }
      numbers.mutable_data()[row] = value;
    }
    if (numeric) {
      columns[py::str(names[k])] = numbers;
    } else {
      py::list strings;
      for (const auto& t : texts) strings.append(py::str(t));
      columns[py::str(names[k])] = asarray(strings, py::arg("dtype") = "str");
    }
  }
  return columns;
}

// A sweep's result with what Python asks of it more than once.
struct PySweepResult {
  SweepResult result;
  bool full = false;
  py::object columns;  // csv_columns(), made on first use
};

py::dict columns_of(PySweepResult& sweep) {
  if (!sweep.columns) sweep.columns = csv_columns(sweep_to_csv(sweep.result, sweep.full));
  return py::reinterpret_borrow<py::dict>(sweep.columns);
}

PoseTable pose_table(const py::object& grid, const py::object& poses) {
  if (grid.is_none() == poses.is_none())
    throw UsageError(
        "give the poses either as grid={name: (start, stop, count), ...} or as poses={name: "
        "values, ...}");
  if (!grid.is_none()) {
    std::vector<GridAxis> axes;
    for (const auto& name : grid.attr("keys")()) {
      const std::string parameter = py::str(name).cast<std::string>();
      const py::object spec = grid[name];
      const auto usage = [&] {
        return UsageError("grid['" + parameter +
                          "']: expected (start, stop, count), e.g. (-0.2, 0.2, 41)");
      };
      if (py::len(spec) != 3) throw usage();
      try {
        const long count = spec[py::int_(2)].cast<long>();
        if (count < 1) throw UsageError("grid['" + parameter + "']: the count must be at least 1");
        axes.push_back(GridAxis{parameter, spec[py::int_(0)].cast<double>(),
                                spec[py::int_(1)].cast<double>(), static_cast<std::size_t>(count)});
      } catch (const py::cast_error&) {
        throw usage();
      }
    }
    return grid_poses(std::move(axes));
  }
  PoseTable table;
  std::vector<VecX> columns;
  for (const auto& name : poses.attr("keys")()) {
    table.parameters.push_back(py::str(name).cast<std::string>());
    columns.push_back(to_vector(poses[name], "poses['" + table.parameters.back() + "']"));
    if (columns.back().size() != columns.front().size())
      throw UsageError("poses['" + table.parameters.back() + "'] has " +
                       std::to_string(columns.back().size()) + " values, poses['" +
                       table.parameters.front() + "'] " + std::to_string(columns.front().size()) +
                       "; give every parameter one value per pose");
  }
  const std::size_t count = columns.empty() ? 0 : static_cast<std::size_t>(columns.front().size());
  table.values.resize(count * columns.size());
  for (std::size_t pose = 0; pose < count; ++pose)
    for (std::size_t k = 0; k < columns.size(); ++k)
      table.values[pose * columns.size() + k] = columns[k][static_cast<Eigen::Index>(pose)];
  return table;
}

PySweepResult run_sweep(const ModelFamily& family, const py::object& grid, const py::object& poses,
                        const SolveOptions& solve_options, bool full,
                        std::optional<std::size_t> threads, const py::object& progress) {
  SweepOptions options;
  options.solve = solve_options;
  options.keep_matrices = full;
  options.threads = threads.value_or(0);
  if (threads && *threads == 0) throw UsageError("threads must be at least 1 (None: every core)");
  if (!progress.is_none()) {
    const SharedPyObject callback = share(progress);
    options.progress = [callback](std::size_t done, std::size_t total) {
      py::gil_scoped_acquire gil;
      (*callback)(done, total);
    };
  }
  const PoseTable table = pose_table(grid, poses);
  PySweepResult result;
  result.full = full;
  try {
    py::gil_scoped_release release;
    result.result = sweep(family, table, options);
  } catch (const PythonBuildError& e) {
    e.restore();  // the defaults' member: the caller's error, raised as the function raised it
    throw py::error_already_set();
  }
  return result;
}

py::array_t<double> parameter_values(const SweepResult& sweep, std::size_t k) {
  const std::size_t count = sweep.poses.size(), width = sweep.poses.parameters.size();
  py::array_t<double> values(static_cast<py::ssize_t>(count));
  for (std::size_t pose = 0; pose < count; ++pose)
    values.mutable_data()[pose] = sweep.poses.values[pose * width + k];
  return values;
}

py::object json_loads(const std::string& text) {
  return py::module_::import("json").attr("loads")(text);
}

}  // namespace

void bind_family(py::module_& m) {
  py::class_<SolveOptions>(m, "SolveOptions",
                           "Options of a solve, named as the C++ SolveOptions' members.")
      .def(py::init(&solve_options), py::arg("solver") = "auto",
           py::arg("accept_idle_motions") = false,
           py::arg("singular_rcond") = SolveOptions{}.singular_rcond,
           py::arg("max_relative_residual") = SolveOptions{}.max_relative_residual,
           py::arg("refinement_steps") = SolveOptions{}.refinement_steps,
           py::arg("warn_condition") = SolveOptions{}.warn_condition, py::kw_only(),
           py::arg("mode") = py::none(), py::arg("critical_load") = py::none())
      .def_property_readonly("solver",
                             [](const SolveOptions& o) { return std::string(to_string(o.solver)); })
      .def_readonly("accept_idle_motions", &SolveOptions::accept_idle_motions)
      .def_readonly("singular_rcond", &SolveOptions::singular_rcond)
      .def_readonly("max_relative_residual", &SolveOptions::max_relative_residual)
      .def_readonly("refinement_steps", &SolveOptions::refinement_steps)
      .def_readonly("warn_condition", &SolveOptions::warn_condition)
      .def_readonly("mode", &SolveOptions::mode,
                    "The analysis mode (AnalysisMode), or None for the model's own.")
      .def_readonly("critical_load", &SolveOptions::critical_load,
                    "Whether to find the critical load factor: None (where the result's "
                    "contract has it), True (always) or False (never).");

  py::class_<Parameter>(m, "Parameter",
                        "A family's parameter: its name, default value and unit (may be '').")
      .def_readonly("name", &Parameter::name)
      .def_readonly("default", &Parameter::default_value)
      .def_readonly("unit", &Parameter::unit)
      .def("__repr__", [](const Parameter& p) {
        return "Parameter('" + p.name +
               "', default=" + py::repr(py::float_(p.default_value)).cast<std::string>() +
               (p.unit.empty() ? "" : ", unit='" + p.unit + "'") + ")";
      });

  py::class_<ModelFamily>(
      m, "ModelFamily",
      "Models of one topology whose numbers depend on named parameters: a parametric model "
      "file (load_family) or a Python function returning a Model (ModelFamily.from_function).")
      .def_property_readonly("name", &ModelFamily::name)
      .def_property_readonly("parameters", &ModelFamily::parameters)
      .def_property_readonly(
          "defaults",
          [](const ModelFamily& f) {
            py::dict d;
            for (const auto& p : f.parameters()) d[py::str(p.name)] = p.default_value;
            return d;
          },
          "{name: default value} of every parameter, in the family's order.")
      .def("_with_defaults",
           [](const ModelFamily& f, const std::map<std::string, double>& values) {
             return f.with_defaults(member_values(f, values));
           })
      .def("_build", &build_member)
      .def("_solve",
           [](const ModelFamily& f, const std::map<std::string, double>& values,
              const SolveOptions& options) {
             const Model member = build_member(f, values);
             return solve(member, options);
           })
      .def("_sweep", &run_sweep)
      .def_static("_from_function", &family_from_function)
      .def("__repr__", [](const ModelFamily& f) {
        std::string text = "<stiffmsa.ModelFamily '" + f.name() + "' of";
        for (std::size_t k = 0; k < f.parameters().size(); ++k)
          text += (k > 0 ? ", " : " ") + f.parameters()[k].name;
        return text + (f.parameters().empty() ? " no parameters>" : ">");
      });

  m.def("_load_family",
        [](const std::filesystem::path& path, const std::map<std::string, double>& values) {
          return load_model_family(path, {}, values);
        });

  py::class_<PySweepResult>(
      m, "SweepResult",
      "One row per pose, as `stiffmsa sweep` writes its CSV: `columns` (every CSV column, "
      "numbers as float64 arrays with NaN for an empty cell), `status` and `message` per "
      "pose, and the summary's worst poses (`worst`).")
      .def_property_readonly("model", [](const PySweepResult& s) { return s.result.model; })
      .def_property_readonly(
          "parameters", [](const PySweepResult& s) { return s.result.poses.parameters; },
          "The swept parameters, in the CSV's order.")
      .def_property_readonly("units", [](const PySweepResult& s) { return s.result.units; })
      .def_property_readonly("end_effectors",
                             [](const PySweepResult& s) { return s.result.end_effectors; })
      .def_property_readonly("full", [](const PySweepResult& s) { return s.full; })
      .def_property_readonly("threads", [](const PySweepResult& s) { return s.result.threads; })
      .def_property_readonly(
          "seconds", [](const PySweepResult& s) { return s.result.seconds; },
          "Wall time of the solves.")
      .def_property_readonly(
          "poses",
          [](const PySweepResult& s) {
            py::dict poses;
            for (std::size_t k = 0; k < s.result.poses.parameters.size(); ++k)
              poses[py::str(s.result.poses.parameters[k])] = parameter_values(s.result, k);
            return poses;
          },
          "{parameter: values per pose}.")
      .def_property_readonly(
          "grid",
          [](const PySweepResult& s) {
            py::dict grid;
            for (const auto& a : s.result.poses.grid)
              grid[py::str(a.parameter)] = py::make_tuple(a.start, a.stop, a.count);
            return grid;
          },
          "{parameter: (start, stop, count)} for a grid, the first varying fastest; {} for a list "
          "of poses.")
      .def_property_readonly(
          "columns", [](PySweepResult& s) { return py::dict(columns_of(s)); },
          "{CSV column name: array}, in the CSV's order.")
      .def_property_readonly("status",
                             [](PySweepResult& s) { return py::object(columns_of(s)["status"]); })
      .def_property_readonly("message",
                             [](PySweepResult& s) { return py::object(columns_of(s)["message"]); })
      .def_property_readonly(
          "summary",
          [](const PySweepResult& s) {
            return json_loads(sweep_summary_to_json(s.result, s.full, ""));
          },
          "The summary file's content (format stiffmsa-sweep/1).")
      .def_property_readonly(
          "worst",
          [](const PySweepResult& s) {
            return py::object(json_loads(sweep_summary_to_json(s.result, s.full, ""))["worst"]);
          },
          "{column: its worst value among the ok poses, with unit, criterion, pose index, CSV line "
          "and parameter "
          "values} (None where no pose is ok).")
      .def(
          "to_csv", [](const PySweepResult& s) { return sweep_to_csv(s.result, s.full); },
          "The CSV's text, as `stiffmsa sweep --csv` writes it.")
      .def(
          "write_csv",
          [](const PySweepResult& s, const std::filesystem::path& path) {
            write_sweep_csv(s.result, s.full, path);
          },
          py::arg("path"), "Writes the CSV (the CLI's file, byte for byte), whole or not at all.")
      .def(
          "write_summary",
          [](const PySweepResult& s, const std::filesystem::path& path, const std::string& csv) {
            write_sweep_summary(s.result, s.full, csv, path);
          },
          py::arg("path"), py::arg("csv") = "",
          "Writes the summary JSON; `csv` is the CSV's name it gives.")
      .def("__len__", [](const PySweepResult& s) { return s.result.results.size(); })
      .def("__repr__", [](const PySweepResult& s) {
        std::size_t ok = 0;
        for (const auto& r : s.result.results) ok += r.status == PoseStatus::ok ? 1 : 0;
        std::string text = "<stiffmsa.SweepResult of '" + s.result.model +
                           "': " + std::to_string(s.result.results.size()) + " poses over";
        for (std::size_t k = 0; k < s.result.poses.parameters.size(); ++k)
          text += (k > 0 ? ", " : " ") + s.result.poses.parameters[k];
        return text + ", " + std::to_string(ok) + " ok>";
      });
}

}  // namespace stiffmsa::python
