// Results of solve(): every quantity of the result file, as numpy arrays keyed by the user's
// names, and the result file itself (to_json, to_dict, write_json) from the library's writer.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "convert.hpp"

namespace stiffmsa::python {

namespace {

template <class Entity>
py::dict by_name(const std::vector<Entity>& entities) {
  py::dict named;
  for (const auto& e : entities) named[py::str(e.name)] = py::cast(e);
  return named;
}

// As the result file writes it: one vector for a two-end joint, a row per further end else.
py::object relative_deflection(const JointResult& joint) {
  if (!joint.relative_deflection) return py::none();
  const auto& q = *joint.relative_deflection;
  if (q.size() == 1) return to_array(q.front());
  MatX rows(static_cast<Eigen::Index>(q.size()), q.empty() ? 0 : q.front().size());
  for (std::size_t k = 0; k < q.size(); ++k)
    rows.row(static_cast<Eigen::Index>(k)) = q[k].transpose();
  return to_array(rows);
}

std::string result_repr(const Result& r) {
  std::string text = "<stiffmsa.Result of '" + r.model + "' (solver " +
                     std::string(to_string(r.report.solver)) + "): end effectors";
  for (std::size_t i = 0; i < r.end_effectors.size(); ++i) {
    const auto& e = r.end_effectors[i];
    text += (i > 0 ? ", " : " ") + e.name;
    if (e.compliance) {
      const PrincipalStiffness k = principal_stiffness(*e.compliance);
      char numbers[96];
      std::snprintf(numbers, sizeof numbers, " (k_trans_min %.4g N/m, k_rot_min %.4g N·m/rad)",
                    k.translational[0], k.rotational[0]);
      text += numbers;
    }
  }
  text += "; " + std::to_string(r.report.warnings.size()) + " warnings>";
  return text;
}

}  // namespace

void bind_results(py::module_& m) {
  py::class_<EndEffectorResult>(
      m, "EndEffectorResult",
      "An end effector's Cartesian compliance C (6×6, [Δp; Δφ] per unit [F; M]), "
      "stiffness K (None where some direction is held rigidly or undetermined) and "
      "deflection under the model's loads (6,).")
      .def_readonly("name", &EndEffectorResult::name)
      .def_readonly("point", &EndEffectorResult::point)
      .def_readonly("link", &EndEffectorResult::link)
      .def_property_readonly(
          "end", [](const EndEffectorResult& e) { return std::string(to_string(e.end)); })
      .def_property_readonly(
          "compliance", [](const EndEffectorResult& e) { return to_optional_array(e.compliance); })
      .def_property_readonly(
          "stiffness", [](const EndEffectorResult& e) { return to_optional_array(e.stiffness); })
      .def_property_readonly(
          "deflection", [](const EndEffectorResult& e) { return to_optional_array(e.deflection); })
      .def("__repr__", [](const EndEffectorResult& e) {
        return "<stiffmsa.EndEffectorResult '" + e.name + "' at '" + e.point + "' on link '" +
               e.link + "'" + (e.stiffness ? "" : ", stiffness None") + ">";
      });

  py::class_<LinkEndResult>(m, "LinkEndResult",
                            "One end of a link: its deflection and the wrench on it (6,).")
      .def_property_readonly("deflection",
                             [](const LinkEndResult& e) { return to_optional_array(e.deflection); })
      .def_property_readonly("wrench",
                             [](const LinkEndResult& e) { return to_optional_array(e.wrench); });

  py::class_<InternalForces>(
      m, "InternalForces",
      "A flexible link's internal forces at a station: `position` (a fraction of the length from "
      "the from end) and `forces` [N, Vy, Vz, T, My, Mz] (6,), local axes, the wrench the part "
      "beyond the station exerts on the part before it (N > 0 is tension).")
      .def_readonly("position", &InternalForces::position)
      .def_property_readonly("forces",
                             [](const InternalForces& f) { return to_array(VecX(f.forces)); })
      .def("__repr__", [](const InternalForces& f) {
        return "<stiffmsa.InternalForces at " +
               py::repr(py::float_(f.position)).cast<std::string>() + ">";
      });

  py::class_<LinkResult>(
      m, "LinkResult", "A link's two ends, `from_` and `to` (link['from'] and link['to'] as well).")
      .def_readonly("name", &LinkResult::name)
      .def_readonly("from_", &LinkResult::from)
      .def_readonly("to", &LinkResult::to)
      .def_readonly("internal_forces", &LinkResult::internal_forces,
                    "Beams: the internal forces at stations from end to end (a list of "
                    "InternalForces); empty for other links.")
      .def("__getitem__",
           [](const LinkResult& link, const std::string& end) {
             if (end == "from") return link.from;
             if (end == "to") return link.to;
             throw py::key_error("a link has ends 'from' and 'to', not '" + end + "'");
           })
      .def("__repr__",
           [](const LinkResult& l) { return "<stiffmsa.LinkResult '" + l.name + "'>"; });

  py::class_<JointResult>(
      m, "JointResult",
      "A joint's relative deflection along its free directions ((p,) for two ends, (m-1, p) "
      "for m ends), the wrench it applies to its first link end (6,) and, for actuated joints, "
      "its effort (p,).")
      .def_readonly("name", &JointResult::name)
      .def_property_readonly("relative_deflection", &relative_deflection)
      .def_property_readonly("wrench",
                             [](const JointResult& j) { return to_optional_array(j.wrench); })
      .def_property_readonly("effort",
                             [](const JointResult& j) { return to_optional_array(j.effort); })
      .def_readonly("actuated", &JointResult::actuated)
      .def("__repr__",
           [](const JointResult& j) { return "<stiffmsa.JointResult '" + j.name + "'>"; });

  py::class_<SupportResult>(m, "SupportResult", "The reaction of a support on its link ends (6,).")
      .def_readonly("name", &SupportResult::name)
      .def_property_readonly("reaction",
                             [](const SupportResult& s) { return to_optional_array(s.reaction); })
      .def("__repr__",
           [](const SupportResult& s) { return "<stiffmsa.SupportResult '" + s.name + "'>"; });

  py::class_<SolveReport>(
      m, "SolveReport",
      "How the solve went: the solver used, accuracy checks, notes (why a value is None) "
      "and warnings.")
      .def_readonly("relative_residual", &SolveReport::relative_residual)
      .def_readonly("equilibrium_error", &SolveReport::equilibrium_error)
      .def_readonly("reciprocal_condition", &SolveReport::reciprocal_condition)
      .def_property_readonly("solver",
                             [](const SolveReport& r) { return std::string(to_string(r.solver)); })
      .def_readonly("notes", &SolveReport::notes)
      .def_readonly("warnings", &SolveReport::warnings)
      .def_readonly("failed_checks", &SolveReport::failed_checks)
      .def_property_readonly("usable", &SolveReport::usable)
      .def("__repr__", [](const SolveReport& r) {
        char text[160];
        std::snprintf(
            text, sizeof text,
            "<stiffmsa.SolveReport solver %s, relative residual %.3g, equilibrium error %.3g>",
            to_string(r.solver), r.relative_residual, r.equilibrium_error);
        return std::string(text);
      });

  py::class_<AnalysisInfo>(m, "AnalysisInfo",
                           "How a result was found: its mode (AnalysisMode) and, in the loaded "
                           "mode, the load steps and Newton iterations it took.")
      .def_readonly("mode", &AnalysisInfo::mode)
      .def_readonly("load_steps", &AnalysisInfo::load_steps)
      .def_readonly("iterations", &AnalysisInfo::iterations)
      .def("__repr__", [](const AnalysisInfo& a) {
        return std::string("<stiffmsa.AnalysisInfo ") + to_string(a.mode) + ", " +
               std::to_string(a.load_steps) + " load steps, " + std::to_string(a.iterations) +
               " iterations>";
      });

  py::class_<CriticalLoad>(
      m, "CriticalLoad",
      "The smallest positive multiplier of a load case's loads at which the structure buckles or "
      "reaches a limit point (`factor`, None where none is positive) and its mode in words.")
      .def_readonly("factor", &CriticalLoad::factor)
      .def_readonly("mode", &CriticalLoad::mode)
      .def("__repr__", [](const CriticalLoad& c) {
        return "<stiffmsa.CriticalLoad " +
               (c.factor ? py::repr(py::float_(*c.factor)).cast<std::string>() : "None") + ">";
      });

  py::class_<Result>(
      m, "Result",
      "Everything a solve found, keyed by the model's names: end_effectors, links, joints, "
      "supports (dicts of name to result), the system size and the report. to_dict() is the "
      "result file's content.")
      .def_readonly("model", &Result::model)
      .def_readonly("load_case", &Result::load_case,
                    "The load case these results are of ('' for the model's unnamed case).")
      .def_readonly("analysis", &Result::analysis)
      .def_readonly("critical_load", &Result::critical_load,
                    "The CriticalLoad where the solve found it: critical_load=True, or None (the "
                    "default) where the result's contract has it; else None.")
      .def_property_readonly(
          "load_cases",
          [](const Result& r) {
            py::dict named;
            for (const auto& c : r.load_cases) named[py::str(c.load_case)] = py::cast(c);
            return named;
          },
          "Every named load case's results (a Result each), by name, in model order.")
      .def_property_readonly(
          "linear",
          [](const Result& r) { return r.linear ? py::cast(Result(*r.linear)) : py::none(); },
          "In the loaded mode, the linear results of the same case (a Result); else None.")
      .def("load_case_result", &Result::load_case_result, py::arg("name"),
           py::return_value_policy::copy,
           "The results of the load case of that name; UsageError naming the nearest name when "
           "there is none.")
      .def_readonly("system", &Result::system)
      .def_property_readonly("end_effectors",
                             [](const Result& r) { return by_name(r.end_effectors); })
      .def_property_readonly("links", [](const Result& r) { return by_name(r.links); })
      .def_property_readonly("joints", [](const Result& r) { return by_name(r.joints); })
      .def_property_readonly("supports", [](const Result& r) { return by_name(r.supports); })
      .def_readonly("report", &Result::report)
      .def("end_effector", &Result::end_effector, py::arg("name"), py::return_value_policy::copy,
           "The end effector of that name; UsageError naming the nearest name when there is none.")
      .def("link", &Result::link, py::arg("name"), py::return_value_policy::copy,
           "The link of that name.")
      .def("joint", &Result::joint, py::arg("name"), py::return_value_policy::copy,
           "The joint of that name.")
      .def("support", &Result::support, py::arg("name"), py::return_value_policy::copy,
           "The support of that name.")
      .def("to_json", &result_to_json,
           "The result file's text (format stiffmsa-result/1), as `stiffmsa solve --json` writes "
           "it.")
      .def(
          "to_dict",
          [](const Result& r) {
            return py::module_::import("json").attr("loads")(result_to_json(r));
          },
          "The result file's content as Python data (json.loads of to_json()).")
      .def(
          "write_json",
          [](const Result& r, const std::filesystem::path& path) { write_result_file(r, path); },
          py::arg("path"), "Writes the result file, whole or not at all.")
      .def("__repr__", &result_repr);

  m.def(
      "_solve",
      [](const Model& model, const SolveOptions& options) { return solve(model, options); },
      py::arg("model"), py::arg("options"));

  py::class_<PrincipalStiffness>(
      m, "PrincipalStiffness",
      "Stiffness against a pure force (translational, N/m) and a pure moment "
      "(rotational, N·m/rad), ascending; inf along a rigidly held direction.")
      .def_property_readonly(
          "translational",
          [](const PrincipalStiffness& k) { return to_array(VecX(k.translational)); })
      .def_property_readonly(
          "rotational", [](const PrincipalStiffness& k) { return to_array(VecX(k.rotational)); });
  m.def(
      "principal_stiffness",
      [](py::object compliance) {
        return principal_stiffness(to_matrix(compliance, "compliance", 6, 6));
      },
      py::arg("compliance"),
      "Eigenvalues, ascending, of the inverses of the 3×3 diagonal blocks of a 6×6 compliance.");
}

}  // namespace stiffmsa::python
