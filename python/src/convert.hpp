#pragma once
// Conversions between Python values and the library's vocabulary, shared by the binding files.
// Numbers arrive as numpy arrays or any sequence; a wrong shape is the caller's error and says
// which argument and what shape was expected (UsageError, raised as stiffmsa.UsageError).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <optional>
#include <string>
#include <vector>

#include "stiffmsa/stiffmsa.hpp"

namespace stiffmsa::python {

namespace py = pybind11;

// An n-vector from a sequence of n numbers (or one number where n = 1).
VecX to_vector(py::handle value, const std::string& what, std::optional<long> size = std::nullopt);
Vec3 to_vec3(py::handle value, const std::string& what);
Vec6 to_vec6(py::handle value, const std::string& what);
// An r×c matrix from nested sequences or a 2-D array (a 1×1 matrix also from one number).
MatX to_matrix(py::handle value, const std::string& what, std::optional<long> rows = std::nullopt,
               std::optional<long> cols = std::nullopt);
std::vector<std::string> to_names(py::handle value, const std::string& what);

// A read-only float64 array of the vector's or matrix's values (copied once, row-major).
py::array_t<double> to_array(const VecX& vector);
py::array_t<double> to_array(const MatX& matrix);
template <class T>
py::object to_optional_array(const std::optional<T>& value) {
  if (!value) return py::none();
  if constexpr (T::ColsAtCompileTime == 1)
    return to_array(VecX(*value));
  else
    return to_array(MatX(*value));
}

// SolveOptions from the keyword arguments named as its members; "auto" is SolverKind::automatic.
// Throws UsageError for an unknown or unavailable solver or a value out of range.
// `mode`: None (the model's own), "linear", "loaded" or an AnalysisMode. `critical_load`: None
// (unset: the result's contract decides), True (always) or False (never), as a bool or a numpy
// bool; another type raises TypeError naming the argument.
SolveOptions solve_options(const std::string& solver, bool accept_idle_motions,
                           double singular_rcond, double max_relative_residual,
                           int refinement_steps, double warn_condition, const py::object& mode,
                           const py::object& critical_load);

void bind_errors(py::module_& m);
void bind_model(py::module_& m);
void bind_results(py::module_& m);
void bind_family(py::module_& m);

}  // namespace stiffmsa::python
