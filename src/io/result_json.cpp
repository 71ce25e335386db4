// The result file "stiffmsa-result/1" (model-format.md, "Result file"). Programs outside this
// repository parse it, so the keys and their nesting are a contract; the layout (one matrix
// row per line) is only for people reading the file.
#include <iterator>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "stiffmsa/io/result_file.hpp"

namespace stiffmsa {
namespace {

// Ordered, so that names appear in model order as the user wrote them.
using Json = nlohmann::ordered_json;

constexpr const char* result_format = "stiffmsa-result/1";

template <class Derived>
Json vector_json(const Eigen::MatrixBase<Derived>& v) {
  Json values = Json::array();
  // Adding +0.0 turns a negative zero (rounding's sign of nothing) into a plain 0.
  for (Eigen::Index i = 0; i < v.size(); ++i) values.push_back(v(i) + 0.0);
  return values;
}

// A list of rows, as the format writes matrices.
Json matrix_json(const Mat6& m) {
  Json rows = Json::array();
  for (Eigen::Index r = 0; r < m.rows(); ++r) rows.push_back(vector_json(m.row(r)));
  return rows;
}

template <class T, class ToJson>
Json or_null(const std::optional<T>& value, ToJson to_json) {
  return value ? to_json(*value) : Json(nullptr);
}

const auto vec6_json = [](const Vec6& v) { return vector_json(v); };
const auto vecx_json = [](const VecX& v) { return vector_json(v); };

// A two-end joint has one relative deflection, written as a flat list; a joint of m > 2 ends
// has m − 1, written as a list of lists.
Json relative_deflection_json(const std::vector<VecX>& per_end) {
  if (per_end.size() == 1) return vector_json(per_end.front());
  Json lists = Json::array();
  for (const VecX& q : per_end) lists.push_back(vector_json(q));
  return lists;
}

// An object of the named entities of one kind, in model order. Built from the list at once:
// ordered_json's operator[] compares the key with every earlier one, which made a 100 000-link
// result take half a minute. The names are unique in a result of a valid model; a Result
// assembled by hand with a repeated name gets the key twice.
template <class Entities, class ToJson>
Json named_objects(const Entities& entities, ToJson to_json) {
  std::vector<std::pair<std::string, Json>> members;
  members.reserve(entities.size());
  for (const auto& entity : entities) members.emplace_back(entity.name, to_json(entity));
  Json j = Json::object();
  j.get_ref<Json::object_t&>() =
      Json::object_t(std::make_move_iterator(members.begin()), std::make_move_iterator(members.end()));
  return j;
}

Json end_effector_json(const EndEffectorResult& e) {
  Json j = Json::object();
  j["point"] = e.point;
  j["link"] = e.link;
  j["compliance"] = or_null(e.compliance, matrix_json);
  j["stiffness"] = or_null(e.stiffness, matrix_json);
  j["deflection"] = or_null(e.deflection, vec6_json);
  return j;
}

Json link_end_json(const LinkEndResult& end) {
  Json j = Json::object();
  j["deflection"] = or_null(end.deflection, vec6_json);
  j["wrench"] = or_null(end.wrench, vec6_json);
  return j;
}

Json joint_json(const JointResult& joint) {
  Json j = Json::object();
  j["relative_deflection"] = or_null(joint.relative_deflection, relative_deflection_json);
  j["wrench"] = or_null(joint.wrench, vec6_json);
  if (joint.actuated || joint.effort) j["effort"] = or_null(joint.effort, vecx_json);
  return j;
}

Json report_json(const SolveReport& report) {
  Json j = Json::object();
  j["solver"] = report.solver;
  j["relative_residual"] = report.relative_residual;
  j["equilibrium_error"] = report.equilibrium_error;
  j["reciprocal_condition"] = report.reciprocal_condition;
  j["notes"] = report.notes;
  j["warnings"] = report.warnings;
  return j;
}

Json result_json(const Result& result) {
  Json j = Json::object();
  j["format"] = result_format;
  j["model"] = result.model;
  j["system"] = Json{{"unknowns", result.system.unknowns},
                     {"equations", result.system.equations},
                     {"nonzeros", result.system.nonzeros}};

  j["end_effectors"] = named_objects(result.end_effectors, end_effector_json);
  j["link_ends"] = named_objects(result.links, [](const LinkResult& link) {
    return Json{{"from", link_end_json(link.from)}, {"to", link_end_json(link.to)}};
  });
  j["joints"] = named_objects(result.joints, joint_json);
  j["supports"] = named_objects(result.supports, [](const SupportResult& s) {
    return Json{{"reaction", or_null(s.reaction, vec6_json)}};
  });
  j["report"] = report_json(result.report);
  return j;
}

// Scalars are written by nlohmann: numbers in their shortest form that reads back to the same
// double (non-finite ones become null), strings escaped. Invalid UTF-8 in a user's name is
// replaced rather than failing the whole write.
std::string scalar_text(const Json& value) {
  return value.dump(-1, ' ', false, Json::error_handler_t::replace);
}

bool holds_only_scalars(const Json& array) {
  for (const Json& element : array) {
    if (element.is_structured()) return false;
  }
  return true;
}

void append_indented(std::string& out, const Json& value, int indent) {
  const std::string inner(static_cast<std::size_t>(indent + 2), ' ');
  const std::string closing(static_cast<std::size_t>(indent), ' ');
  if (value.is_object()) {
    if (value.empty()) {
      out += "{}";
      return;
    }
    out += "{\n";
    bool first = true;
    for (const auto& [key, member] : value.items()) {
      if (!first) out += ",\n";
      first = false;
      out += inner + scalar_text(Json(key)) + ": ";
      append_indented(out, member, indent + 2);
    }
    out += "\n" + closing + "}";
  } else if (value.is_array()) {
    if (holds_only_scalars(value)) {
      // A vector, or one matrix row, on one line.
      out += "[";
      for (std::size_t i = 0; i < value.size(); ++i) {
        if (i > 0) out += ", ";
        out += scalar_text(value[i]);
      }
      out += "]";
      return;
    }
    out += "[\n";
    for (std::size_t i = 0; i < value.size(); ++i) {
      if (i > 0) out += ",\n";
      out += inner;
      append_indented(out, value[i], indent + 2);
    }
    out += "\n" + closing + "]";
  } else {
    out += scalar_text(value);
  }
}

}  // namespace

std::string result_to_json(const Result& result) {
  std::string text;
  append_indented(text, result_json(result), 0);
  text += '\n';
  return text;
}

void write_result_file(const Result& result, const std::filesystem::path& path) {
  write_file_atomically(path, result_to_json(result));
}

}  // namespace stiffmsa
