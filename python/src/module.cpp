// stiffmsa._core: the library's C++ API seen from Python. The package stiffmsa (python/stiffmsa)
// re-exports it with the exceptions of stiffmsa.errors. The bindings never print: every failure
// is an exception.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "convert.hpp"
#include "stiffmsa/config.hpp"

namespace stiffmsa::python {

namespace {

std::string shape_text(const py::array& array) {
  std::string text = "(";
  for (py::ssize_t k = 0; k < array.ndim(); ++k)
    text += (k > 0 ? ", " : "") + std::to_string(array.shape(k));
  return text + (array.ndim() == 1 ? ",)" : ")");
}

using FloatArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

FloatArray as_float_array(py::handle value, const std::string& what) {
  FloatArray array = FloatArray::ensure(value);  // null, with the error cleared, when not numbers
  if (!array)
    throw UsageError(what + ": expected numbers, got " + py::repr(value).cast<std::string>());
  return array;
}

py::object error_class(const char* name) {
  return py::module_::import("stiffmsa.errors").attr(name);
}

void raise(const char* class_name, py::object instance) {
  const py::object cls = error_class(class_name);
  PyErr_SetObject(cls.ptr(), instance.ptr());
}

py::object optional_text(const std::string& text) {
  return text.empty() ? py::none() : py::cast(text);
}
py::object optional_position(int value) { return value > 0 ? py::cast(value) : py::none(); }

// An option of three states: None (unset), or a bool, Python's or numpy's. Anything else is a
// TypeError naming the argument and the values it takes (`expected`): an int is refused too,
// where 0 would be read as "never" by one caller and as "not asked" by another.
std::optional<bool> optional_flag(const py::object& value, const std::string& argument,
                                  const std::string& expected) {
  if (value.is_none()) return std::nullopt;
  if (py::isinstance<py::bool_>(value) ||
      py::isinstance(value, py::module_::import("numpy").attr("bool_")))
    return value.cast<bool>();
  throw py::type_error(argument + ": expected " + expected + ", got " +
                       py::repr(value).cast<std::string>() + " (" + Py_TYPE(value.ptr())->tp_name +
                       ")");
}

}  // namespace

VecX to_vector(py::handle value, const std::string& what, std::optional<long> size) {
  const auto array = as_float_array(value, what);
  const bool scalar_for_one = array.ndim() == 0 && (!size || *size == 1);
  if (!scalar_for_one && (array.ndim() != 1 || (size && array.shape(0) != *size))) {
    throw UsageError(what + ": expected " +
                     (size ? std::to_string(*size) + " numbers" : "a list of numbers") +
                     ", got an array of shape " + shape_text(array));
  }
  VecX vector(array.size());
  for (py::ssize_t i = 0; i < array.size(); ++i) vector[i] = array.data()[i];
  return vector;
}

Vec3 to_vec3(py::handle value, const std::string& what) { return to_vector(value, what, 3); }
Vec6 to_vec6(py::handle value, const std::string& what) { return to_vector(value, what, 6); }

MatX to_matrix(py::handle value, const std::string& what, std::optional<long> rows,
               std::optional<long> cols) {
  const auto array = as_float_array(value, what);
  const bool one_by_one = rows.value_or(1) == 1 && cols.value_or(1) == 1;
  if (array.ndim() == 0 && one_by_one) return MatX::Constant(1, 1, *array.data());
  if (array.ndim() != 2 || (rows && array.shape(0) != *rows) || (cols && array.shape(1) != *cols)) {
    const std::string expected =
        rows && cols ? std::to_string(*rows) + "×" + std::to_string(*cols) + " matrix"
                     : std::string("matrix (a list of rows)");
    throw UsageError(what + ": expected a " + expected + ", got an array of shape " +
                     shape_text(array));
  }
  MatX matrix(array.shape(0), array.shape(1));
  for (py::ssize_t r = 0; r < array.shape(0); ++r)
    for (py::ssize_t c = 0; c < array.shape(1); ++c) matrix(r, c) = *array.data(r, c);
  return matrix;
}

std::vector<std::string> to_names(py::handle value, const std::string& what) {
  if (py::isinstance<py::str>(value)) return {value.cast<std::string>()};
  try {
    return value.cast<std::vector<std::string>>();
  } catch (const py::cast_error&) {
    throw UsageError(what + ": expected a name or a list of names");
  }
}

py::array_t<double> to_array(const VecX& vector) {
  py::array_t<double> array(vector.size());
  std::copy(vector.data(), vector.data() + vector.size(), array.mutable_data());
  array.attr("flags").attr("writeable") = false;
  return array;
}

py::array_t<double> to_array(const MatX& matrix) {
  py::array_t<double> array({matrix.rows(), matrix.cols()});
  auto view = array.mutable_unchecked<2>();
  for (Eigen::Index r = 0; r < matrix.rows(); ++r)
    for (Eigen::Index c = 0; c < matrix.cols(); ++c) view(r, c) = matrix(r, c);
  array.attr("flags").attr("writeable") = false;
  return array;
}

SolveOptions solve_options(const std::string& solver, bool accept_idle_motions,
                           double singular_rcond, double max_relative_residual,
                           int refinement_steps, double warn_condition, const py::object& mode,
                           const py::object& critical_load) {
  SolveOptions options;
  if (py::isinstance<AnalysisMode>(mode)) {
    options.mode = mode.cast<AnalysisMode>();
  } else if (!mode.is_none()) {
    const auto parsed = py::isinstance<py::str>(mode)
                            ? analysis_mode_from_string(mode.cast<std::string>())
                            : std::nullopt;
    if (!parsed)
      throw UsageError("mode " + py::repr(mode).cast<std::string>() +
                       ": expected \"linear\", \"loaded\" or None (the model's own)");
    options.mode = parsed;
  }
  options.critical_load = optional_flag(critical_load, "critical_load",
                                        "None (where the result's contract has it), True "
                                        "(always) or False (never)");
  const auto kind = solver_kind_from_string(solver);
  if (!kind)
    throw UsageError("solver '" + solver + "': expected one of auto, sparse_lu, umfpack, klu");
  if (!solver_available(*kind))
    throw UsageError("solver '" + solver +
                     "' is not available in this build of stiffmsa (built without "
                     "SuiteSparse); use solver=\"auto\" or \"sparse_lu\"");
  options.solver = *kind;
  options.accept_idle_motions = accept_idle_motions;
  options.singular_rcond = singular_rcond;
  options.max_relative_residual = max_relative_residual;
  options.refinement_steps = refinement_steps;
  options.warn_condition = warn_condition;
  options.validate();
  return options;
}

void bind_errors(py::module_&) {
  // The exception classes live in stiffmsa/errors.py, so that they can be caught and subclassed
  // like any Python exception; the C++ errors are turned into them here.
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      if (thrown) std::rethrow_exception(thrown);
    } catch (const InputError& e) {
      const py::object diagnostic = error_class("Diagnostic");
      py::list diagnostics;
      for (const auto& d : e.diagnostics())
        diagnostics.append(
            diagnostic(optional_text(d.location.file), optional_position(d.location.line),
                       optional_position(d.location.column), d.key_path, d.message, d.to_string()));
      raise("InputError", error_class("InputError")(e.what(), diagnostics));
    } catch (const SingularModelError& e) {
      const char* cause =
          e.cause() == SingularModelError::Cause::free_motion ? "free_motion" : "numerical";
      raise("SingularModelError",
            error_class("SingularModelError")(e.summary(), cause, e.details()));
    } catch (const NoEquilibriumError& e) {
      raise("NoEquilibriumError", error_class("NoEquilibriumError")(e.what(), e.load_factor()));
    } catch (const IoError& e) {
      raise("IoError", error_class("IoError")(e.what()));
    } catch (const NameError& e) {
      const py::object suggestion = e.suggestion() ? py::cast(*e.suggestion()) : py::none();
      raise("NameError", error_class("NameError")(e.what(), e.kind(), e.name(), suggestion));
    } catch (const UsageError& e) {
      raise("UsageError", error_class("UsageError")(e.what()));
    } catch (const Error& e) {
      raise("Error", error_class("Error")(e.what()));
    }
  });
}

}  // namespace stiffmsa::python

PYBIND11_MODULE(_core, m) {
  m.doc() = "The compiled core of stiffmsa; use the package `stiffmsa`, which re-exports it.";
  using namespace stiffmsa::python;
  m.attr("__version__") = STIFFMSA_VERSION;
  bind_errors(m);
  bind_model(m);
  bind_results(m);
  bind_family(m);
}
