// The result file "stiffmsa-result/1" (model-format.md, "Result file"). Programs outside this
// repository parse it, so the keys and their nesting are a contract; the layout (two spaces
// per level, a vector or one matrix row per line) is only for people reading the file.
//
// The text is written straight from the Result, without a JSON document in between: a
// 100 000-link result holds 2.4 million numbers, and building, printing and freeing a
// document node for each took longer than the solve.
#include <algorithm>
#include <array>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string_view>
#include <vector>

#include "stiffmsa/analysis.hpp"
#include "stiffmsa/io/result_file.hpp"
#include "stiffmsa/number_text.hpp"

namespace stiffmsa {
namespace {

constexpr const char* result_format = "stiffmsa-result/1";

class ResultWriter {
 public:
  std::string text;

  // Numbers in the shortest form that reads back to the same double, with ".0" on integral
  // values so that they read as reals; non-finite ones (which JSON lacks) become null.
  void number(double value) {
    if (!std::isfinite(value)) {
      text += "null";
      return;
    }
    if (value == 0) {  // either zero: a result's many unloaded parts, without the formatter
      text += "0.0";
      return;
    }
    const std::size_t start = text.size();
    append_shortest_text(text, value);
    // A scan of the few characters written: find_first_of searches its set once per character.
    if (std::none_of(text.begin() + static_cast<std::ptrdiff_t>(start), text.end(),
                     [](char c) { return c == '.' || c == 'e'; }))
      text += ".0";
  }
  void integer(long value) { text += std::to_string(value); }
  void boolean(bool value) { text += value ? "true" : "false"; }
  // Principal stiffnesses (null where unbounded) and their directions, one per row.
  void principal(const Vec3& values, const Mat3& directions) {
    object([&] {
      member("values", [&] { vector(values); });
      member("directions", [&] { list(3, [&](Eigen::Index i) { vector(directions.col(i)); }); });
    });
  }
  // Escaped by nlohmann; invalid UTF-8 in a user's name is replaced rather than failing. A
  // name of printable ASCII without `"` or `\`, which nlohmann writes as it is, is written so
  // directly.
  void string(const std::string& value) {
    const bool as_is = std::all_of(value.begin(), value.end(), [](char c) {
      return c >= 0x20 && c <= 0x7e && c != '"' && c != '\\';
    });
    if (as_is) {
      text += '"';
      text += value;
      text += '"';
      return;
    }
    text += nlohmann::json(value).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  }
  void null() { text += "null"; }

  // A vector, or one matrix row, on one line.
  template <class Derived>
  void vector(const Eigen::MatrixBase<Derived>& v) {
    text += '[';
    for (Eigen::Index i = 0; i < v.size(); ++i) {
      if (i > 0) text += ", ";
      number(v(i));
    }
    text += ']';
  }
  void matrix(const Mat6& m) {
    list(m.rows(), [&](Eigen::Index r) { vector(m.row(r)); });
  }
  void strings(const std::vector<std::string>& values) {
    text += '[';
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (i > 0) text += ", ";
      string(values[i]);
    }
    text += ']';
  }

  // A list of structured values, one per line: item(i) writes the i-th.
  template <class Item>
  void list(Eigen::Index count, Item item) {
    if (count == 0) {
      text += "[]";
      return;
    }
    text += "[\n";
    ++depth_;
    for (Eigen::Index i = 0; i < count; ++i) {
      if (i > 0) text += ",\n";
      indent();
      item(i);
    }
    --depth_;
    text += '\n';
    indent();
    text += ']';
  }

  // An object: members(*this) calls member() for each key in order.
  template <class Members>
  void object(Members members) {
    const std::size_t start = text.size();
    text += "{\n";
    ++depth_;
    first_member_ = true;
    members();
    --depth_;
    if (first_member_) {  // no member: {}
      text.resize(start);
      text += "{}";
      first_member_ = false;
      return;
    }
    text += '\n';
    indent();
    text += '}';
    first_member_ = false;
  }
  // A member of the object being written: value() writes its value. The format's own keys
  // are plain identifiers, written as they are; a user's names are escaped.
  template <class Value>
  void member(std::string_view key, Value value) {
    next_member();
    text += '"';
    text += key;
    text += "\": ";
    value();
  }
  template <class Value>
  void named(const std::string& name, Value value) {
    next_member();
    string(name);
    text += ": ";
    value();
  }

 private:
  void next_member() {
    if (!first_member_) text += ",\n";
    first_member_ = false;
    indent();
  }
  void indent() { text.append(static_cast<std::size_t>(2 * depth_), ' '); }
  int depth_ = 0;
  bool first_member_ = false;
};

template <class T, class Write>
auto or_null(ResultWriter& out, const std::optional<T>& value, Write write) {
  return [&out, &value, write] {
    if (value)
      write(*value);
    else
      out.null();
  };
}

// One station on one line: {"position": …, "N": …, "Vy": …, …}.
void write_internal_forces(ResultWriter& out, const InternalForces& f) {
  static constexpr std::array<const char*, 6> names = {"N", "Vy", "Vz", "T", "My", "Mz"};
  out.text += "{\"position\": ";
  out.number(f.position);
  for (std::size_t i = 0; i < names.size(); ++i) {
    out.text += ", \"";
    out.text += names[i];
    out.text += "\": ";
    out.number(f.forces(static_cast<Eigen::Index>(i)));
  }
  out.text += '}';
}

void write_result(ResultWriter& out, const Result& result) {
  auto vector = [&](const auto& v) { out.vector(v); };
  auto mat6 = [&](const Mat6& m) { out.matrix(m); };
  out.object([&] {
    out.member("format", [&] { out.string(result_format); });
    out.member("model", [&] { out.string(result.model); });
    // Only where the model names load cases: which case the keys beside it are of.
    if (!result.load_cases.empty() || !result.load_case.empty())
      out.member("load_case", [&] { out.string(result.load_case); });
    out.member("parameters", [&] {
      out.object([&] {
        for (const ParameterValue& p : result.parameters)
          out.named(p.name, [&] {
            out.object([&] {
              out.member("value", [&] { out.number(p.value); });
              out.member("unit", [&] { out.string(p.unit); });
              out.member("set", [&] { out.boolean(p.set); });
            });
          });
      });
    });
    out.member("system", [&] {
      out.object([&] {
        out.member("unknowns", [&] { out.integer(result.system.unknowns); });
        out.member("equations", [&] { out.integer(result.system.equations); });
        out.member("nonzeros", [&] { out.integer(result.system.nonzeros); });
      });
    });
    // Named entities in model order. The names are unique in a result of a valid model; a
    // Result assembled by hand with a repeated name gets the key twice.
    out.member("end_effectors", [&] {
      out.object([&] {
        for (const EndEffectorResult& e : result.end_effectors)
          out.named(e.name, [&] {
            out.object([&] {
              out.member("point", [&] { out.string(e.point); });
              out.member("link", [&] { out.string(e.link); });
              out.member("compliance", or_null(out, e.compliance, mat6));
              out.member("stiffness", or_null(out, e.stiffness, mat6));
              out.member("deflection", or_null(out, e.deflection, vector));
              // Only where the stiffness is null because some directions are held rigidly.
              if (e.reduced_stiffness)
                out.member("reduced_stiffness", [&] {
                  out.object([&] {
                    for (const auto& [key, m] :
                         {std::pair{"directions", &e.reduced_stiffness->directions},
                          std::pair{"matrix", &e.reduced_stiffness->matrix}})
                      out.member(key, [&, m = m] {
                        out.list(m->rows(), [&](Eigen::Index r) { out.vector(m->row(r)); });
                      });
                  });
                });
              out.member("principal_stiffness", [&] {
                if (!e.compliance) return out.null();
                const PrincipalStiffness principal = principal_stiffness(*e.compliance);
                out.object([&] {
                  out.member("translational", [&] {
                    out.principal(principal.translational, principal.translational_directions);
                  });
                  out.member("rotational", [&] {
                    out.principal(principal.rotational, principal.rotational_directions);
                  });
                });
              });
              if (e.along_direction)
                out.member("along_direction", [&] {
                  out.object([&] {
                    out.member("direction", [&] { out.vector(e.along_direction->direction); });
                    out.member("translational",
                               [&] { out.number(e.along_direction->translational); });
                    out.member("rotational", [&] { out.number(e.along_direction->rotational); });
                  });
                });
              // Only in the loaded mode.
              if (e.stiffness_asymmetry)
                out.member("stiffness_asymmetry", [&] { out.number(*e.stiffness_asymmetry); });
              // Only where the model has self-weight loads (a robot block's `gravity:`).
              if (e.deflection_gravity)
                out.member("deflection_gravity", [&] { vector(*e.deflection_gravity); });
              // Only for an end effector with axes of its own (a robot frame's, `axes: frame`).
              if (e.in_own_axes)
                out.member("in_own_axes", [&] {
                  out.object([&] {
                    const auto& in = *e.in_own_axes;
                    out.member("axes", [&] {
                      out.list(3, [&](Eigen::Index r) { out.vector(in.axes.row(r)); });
                    });
                    out.member("compliance", or_null(out, in.compliance, mat6));
                    out.member("stiffness", or_null(out, in.stiffness, mat6));
                    out.member("deflection", or_null(out, in.deflection, vector));
                    if (in.deflection_gravity)
                      out.member("deflection_gravity", [&] { vector(*in.deflection_gravity); });
                  });
                });
            });
          });
      });
    });
    out.member("link_ends", [&] {
      out.object([&] {
        for (const LinkResult& link : result.links)
          out.named(link.name, [&] {
            out.object([&] {
              for (const auto& [name, end] :
                   {std::pair{"from", &link.from}, std::pair{"to", &link.to}})
                out.member(name, [&, end = end] {
                  out.object([&] {
                    out.member("deflection", or_null(out, end->deflection, vector));
                    out.member("wrench", or_null(out, end->wrench, vector));
                  });
                });
              // Only where the model loads links along their length (beams).
              if (!link.internal_forces.empty())
                out.member("internal_forces", [&] {
                  out.list(
                      static_cast<Eigen::Index>(link.internal_forces.size()), [&](Eigen::Index k) {
                        const InternalForces& f = link.internal_forces[static_cast<std::size_t>(k)];
                        write_internal_forces(out, f);
                      });
                });
            });
          });
      });
    });
    out.member("joints", [&] {
      out.object([&] {
        for (const JointResult& joint : result.joints)
          out.named(joint.name, [&] {
            out.object([&] {
              // A two-end joint has one relative deflection, written as a flat list; a joint of
              // m > 2 ends has m − 1, written as a list of lists.
              out.member("relative_deflection",
                         or_null(out, joint.relative_deflection, [&](const std::vector<VecX>& q) {
                           if (q.size() == 1)
                             out.vector(q.front());
                           else
                             out.list(static_cast<Eigen::Index>(q.size()), [&](Eigen::Index k) {
                               out.vector(q[static_cast<std::size_t>(k)]);
                             });
                         }));
              out.member("wrench", or_null(out, joint.wrench, vector));
              if (joint.actuated || joint.effort)
                out.member("effort", or_null(out, joint.effort, vector));
            });
          });
      });
    });
    out.member("supports", [&] {
      out.object([&] {
        for (const SupportResult& s : result.supports)
          out.named(s.name, [&] {
            out.object([&] { out.member("reaction", or_null(out, s.reaction, vector)); });
          });
      });
    });
    // Only where the analysis asked for it (SolveOptions::critical_load).
    if (result.critical_load) {
      const CriticalLoad& critical = *result.critical_load;
      out.member("critical_load_factor", [&] {
        if (critical.factor)
          out.number(*critical.factor);
        else
          out.null();
      });
      out.member("critical_load_mode", [&] { out.string(critical.mode); });
    }
    out.member("report", [&] {
      out.object([&] {
        const SolveReport& report = result.report;
        out.member("solver", [&] { out.string(to_string(report.solver)); });
        out.member("relative_residual", [&] { out.number(report.relative_residual); });
        out.member("equilibrium_error", [&] { out.number(report.equilibrium_error); });
        out.member("reciprocal_condition", [&] { out.number(report.reciprocal_condition); });
        out.member("notes", [&] { out.strings(report.notes); });
        out.member("warnings", [&] { out.strings(report.warnings); });
      });
    });
    // Only where the model names load cases: each case's results, with the keys above.
    if (!result.load_cases.empty())
      out.member("load_cases", [&] {
        out.object([&] {
          for (const Result& c : result.load_cases)
            out.named(c.load_case, [&] { write_result(out, c); });
        });
      });
    // Only in the loaded mode: how the equilibrium was reached, and the linear results.
    if (result.analysis.mode == AnalysisMode::loaded) {
      out.member("analysis", [&] {
        out.object([&] {
          out.member("mode", [&] { out.string(to_string(result.analysis.mode)); });
          out.member("load_steps", [&] { out.integer(result.analysis.load_steps); });
          out.member("iterations", [&] { out.integer(result.analysis.iterations); });
        });
      });
      if (result.linear) out.member("linear", [&] { write_result(out, *result.linear); });
    }
  });
}

}  // namespace

std::string result_to_json(const Result& result) {
  ResultWriter out;
  // About 40 bytes per number: one growth of the text instead of many.
  out.text.reserve(4096 + 40 * (12 * 2 * result.links.size() + 90 * result.end_effectors.size()));
  write_result(out, result);
  out.text += '\n';
  return std::move(out.text);
}

void write_result_file(const Result& result, const std::filesystem::path& path) {
  write_file_atomically(path, result_to_json(result));
}

}  // namespace stiffmsa
