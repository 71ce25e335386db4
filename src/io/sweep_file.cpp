#include "stiffmsa/io/sweep_file.hpp"

#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/plain_number.hpp"
#include "stiffmsa/io/result_file.hpp"
#include "stiffmsa/number_text.hpp"

namespace stiffmsa {

std::optional<double> parse_plain_number(std::string_view text) { return detail::plain_number(text); }

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---- reading poses -----------------------------------------------------------------------

std::string trimmed(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t\r");
  return std::string(text.substr(first, last - first + 1));
}

// Fields of one CSV line; a quoted field (RFC 4180, as spreadsheets and our own writer quote)
// loses its quotes and keeps its commas.
std::vector<std::string> split_fields(std::string_view line) {
  std::vector<std::string> fields;
  std::string field;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"' && trimmed(field).empty()) {
      quoted = true;
      field.clear();
    } else if (c == ',') {
      fields.push_back(trimmed(field));
      field.clear();
    } else {
      field += c;
    }
  }
  fields.push_back(trimmed(field));
  return fields;
}

// ---- writing -----------------------------------------------------------------------------

// Shortest text that reads back as the same double; "inf" for an unbounded stiffness, and
// nothing for a value the pose does not have.
void append_number(std::string& out, double value) {
  if (!std::isnan(value)) append_shortest_text(out, value);
}

// RFC 4180: a field with a comma, quote or line break is quoted, its quotes doubled.
void append_text(std::string& out, const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) {
    out += text;
    return;
  }
  out += '"';
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
}

const char* const kMeasureNames[] = {"k_trans_min", "k_trans_max", "k_rot_min",
                                     "k_rot_max",   "deflection_trans", "deflection_rot"};
const char* const kMeasureUnits[] = {"N/m", "N/m", "N·m/rad", "N·m/rad", "m", "rad"};

// The unit of entry (row, col) of a compliance or stiffness over [Δp; Δφ] and [F; M].
std::string matrix_unit(SweepQuantity quantity, int row, int col) {
  const bool translation_row = row < 3, force_col = col < 3;
  if (quantity == SweepQuantity::compliance) {
    if (translation_row) return force_col ? "m/N" : "m/(N·m)";
    return force_col ? "rad/N" : "rad/(N·m)";
  }
  if (translation_row) return force_col ? "N/m" : "N/rad";
  return force_col ? "N·m/m" : "N·m/rad";
}

nlohmann::json json_number(double value) {
  if (std::isnan(value)) return nullptr;
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  return value;
}

}  // namespace

PoseTable parse_pose_table(std::string_view text, const std::string& file_name) {
  // Spreadsheets start a UTF-8 CSV with a byte-order mark; it is not part of the first name.
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
  PoseTable table;
  std::size_t line_number = 0;
  std::size_t start = 0;
  std::vector<Diagnostic> defects;
  const auto defect = [&](std::size_t line, int column, const std::string& key, std::string message) {
    defects.push_back({{file_name, static_cast<int>(line), column}, key, std::move(message)});
  };
  while (start <= text.size()) {
    const auto end = text.find('\n', start);
    const std::string_view line = text.substr(start, end == std::string_view::npos ? text.npos : end - start);
    start = end == std::string_view::npos ? text.size() + 1 : end + 1;
    ++line_number;
    const std::string content = trimmed(line);
    if (content.empty() || content[0] == '#') continue;
    auto fields = split_fields(line);
    if (table.parameters.empty()) {
      for (std::size_t k = 0; k < fields.size(); ++k) {
        if (fields[k].empty())
          defect(line_number, 0, "", "column " + std::to_string(k + 1) + " of the header has no parameter name");
        for (std::size_t j = 0; j < k; ++j)
          if (!fields[k].empty() && fields[j] == fields[k])
            defect(line_number, 0, fields[k], "the parameter '" + fields[k] + "' heads two columns");
      }
      table.parameters = std::move(fields);
      continue;
    }
    if (fields.size() != table.parameters.size()) {
      defect(line_number, 0, "",
             "expected " + counted(table.parameters.size(), "value") + " (one per parameter of the header), got " +
                 std::to_string(fields.size()));
      continue;
    }
    for (std::size_t k = 0; k < fields.size(); ++k) {
      const auto value = detail::plain_number(fields[k]);
      if (!value) defect(line_number, 0, table.parameters[k], "expected a finite number, got '" + fields[k] + "'");
      table.values.push_back(value.value_or(kNaN));
    }
    if (defects.size() >= 20) break;  // a wrong file says so in a screenful
  }
  if (table.parameters.empty() && defects.empty())
    defect(1, 0, "", "the file has no header line naming the parameters");
  else if (table.values.empty() && defects.empty())
    defect(line_number, 0, "", "the file names parameters but lists no poses");
  if (!defects.empty()) throw InputError(std::move(defects));
  return table;
}

PoseTable read_pose_table(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::error_code error;
  if (!in || std::filesystem::is_directory(file, error))
    throw IoError("cannot read the pose file '" + file.string() + "'");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw IoError("cannot read the pose file '" + file.string() + "'");
  return parse_pose_table(text.str(), file.string());
}

std::vector<SweepColumn> sweep_columns(const SweepResult& sweep, bool full) {
  std::vector<SweepColumn> columns;
  for (std::size_t e = 0; e < sweep.end_effectors.size(); ++e) {
    const std::string& effector = sweep.end_effectors[e];
    for (int q = 0; q < 6; ++q)
      columns.push_back({effector + "." + kMeasureNames[q], kMeasureUnits[q], static_cast<SweepQuantity>(q), e, 0, 0,
                         q >= static_cast<int>(SweepQuantity::deflection_trans)});
    columns.push_back({effector + ".cond_trans", "", SweepQuantity::cond_trans, e, 0, 0, true});
    if (sweep.direction) {
      columns.push_back({effector + ".k_trans_dir", "N/m", SweepQuantity::k_trans_dir, e, 0, 0, false});
      columns.push_back({effector + ".k_rot_dir", "N·m/rad", SweepQuantity::k_rot_dir, e, 0, 0, false});
    }
    if (!full) continue;
    for (const auto& [quantity, letter] :
         {std::pair{SweepQuantity::compliance, 'C'}, std::pair{SweepQuantity::stiffness, 'K'}})
      for (int row = 0; row < 6; ++row)
        for (int col = 0; col < 6; ++col)
          columns.push_back({effector + "." + letter + std::to_string(row + 1) + std::to_string(col + 1),
                             matrix_unit(quantity, row, col), quantity, e, row, col,
                             quantity == SweepQuantity::compliance || row != col});
  }
  return columns;
}

std::optional<SweepColumn> find_sweep_column(const SweepResult& sweep, const std::string& name) {
  for (auto& column : sweep_columns(sweep, true))
    if (column.name == name) return column;
  return std::nullopt;
}

double column_value(const SweepResult& sweep, const SweepColumn& column, std::size_t pose) {
  const PoseResult& result = sweep.results[pose];
  if (result.status != PoseStatus::ok || column.end_effector >= result.end_effectors.size()) return kNaN;
  const EndEffectorMeasures& m = result.end_effectors[column.end_effector];
  switch (column.quantity) {
    case SweepQuantity::k_trans_min: return m.principal.translational(0);
    case SweepQuantity::k_trans_max: return m.principal.translational(2);
    case SweepQuantity::k_rot_min: return m.principal.rotational(0);
    case SweepQuantity::k_rot_max: return m.principal.rotational(2);
    case SweepQuantity::deflection_trans: return m.deflection_translation;
    case SweepQuantity::deflection_rot: return m.deflection_rotation;
    case SweepQuantity::compliance: return m.compliance ? (*m.compliance)(column.row, column.col) : kNaN;
    case SweepQuantity::stiffness: return m.stiffness ? (*m.stiffness)(column.row, column.col) : kNaN;
    case SweepQuantity::cond_trans: return m.principal.translational_condition();
    case SweepQuantity::k_trans_dir: return m.along_direction ? m.along_direction->translational : kNaN;
    case SweepQuantity::k_rot_dir: return m.along_direction ? m.along_direction->rotational : kNaN;
  }
  return kNaN;
}

std::optional<std::size_t> worst_pose(const SweepResult& sweep, const SweepColumn& column) {
  std::optional<std::size_t> worst;
  double worst_value = 0;
  const bool by_magnitude = column.quantity == SweepQuantity::compliance || column.quantity == SweepQuantity::stiffness;
  for (std::size_t pose = 0; pose < sweep.results.size(); ++pose) {
    double value = column_value(sweep, column, pose);
    if (std::isnan(value)) continue;
    if (by_magnitude) value = std::abs(value);
    const bool worse = column.worst_is_largest ? value > worst_value : value < worst_value;
    if (!worst || worse) {
      worst = pose;
      worst_value = value;
    }
  }
  return worst;
}

std::string sweep_to_csv(const SweepResult& sweep, bool full) {
  const auto columns = sweep_columns(sweep, full);
  std::string out;
  for (const auto& p : sweep.poses.parameters) {
    append_text(out, p);
    out += ',';
  }
  out += "status,message";
  for (const auto& c : columns) {
    out += ',';
    append_text(out, c.name);
  }
  out += '\n';
  for (std::size_t pose = 0; pose < sweep.results.size(); ++pose) {
    for (double value : sweep.poses.pose(pose)) {
      append_number(out, value);
      out += ',';
    }
    out += to_string(sweep.results[pose].status);
    out += ',';
    append_text(out, sweep.results[pose].message);
    for (const auto& c : columns) {
      out += ',';
      append_number(out, column_value(sweep, c, pose));
    }
    out += '\n';
  }
  return out;
}

std::string sweep_summary_to_json(const SweepResult& sweep, bool full, const std::string& csv_file) {
  using nlohmann::json;
  json summary;
  summary["format"] = "stiffmsa-sweep/1";
  summary["model"] = sweep.model;
  if (!csv_file.empty()) summary["csv"] = csv_file;
  summary["poses"] = sweep.results.size();
  json parameters = json::array();
  for (std::size_t k = 0; k < sweep.poses.parameters.size(); ++k) {
    json p{{"name", sweep.poses.parameters[k]}, {"unit", k < sweep.units.size() ? sweep.units[k] : ""}};
    for (const auto& axis : sweep.poses.grid)
      if (axis.parameter == sweep.poses.parameters[k])
        p["grid"] = {{"start", axis.start}, {"stop", axis.stop}, {"count", axis.count}};
    parameters.push_back(std::move(p));
  }
  summary["parameters"] = std::move(parameters);
  json fixed = json::object();
  for (const ParameterValue& p : sweep.fixed_parameters)
    fixed[p.name] = {{"value", p.value}, {"unit", p.unit}, {"set", p.set}};
  summary["fixed_parameters"] = std::move(fixed);
  if (sweep.direction) summary["direction"] = {(*sweep.direction)(0), (*sweep.direction)(1), (*sweep.direction)(2)};
  json counts;
  for (auto status : {PoseStatus::ok, PoseStatus::singular, PoseStatus::free_motion, PoseStatus::invalid}) {
    std::size_t n = 0;
    for (const auto& r : sweep.results) n += r.status == status ? 1 : 0;
    counts[to_string(status)] = n;
  }
  summary["status"] = std::move(counts);
  std::size_t large = 0;
  for (const auto& r : sweep.results) large += r.large_deflection ? 1 : 0;
  summary["large_deflection"] = large;
  summary["warnings"] = sweep.warnings;
  json worst = json::object();
  for (const auto& column : sweep_columns(sweep, full)) {
    const auto pose = worst_pose(sweep, column);
    if (!pose) {
      worst[column.name] = nullptr;
      continue;
    }
    json at = json::object();
    const auto values = sweep.poses.pose(*pose);
    for (std::size_t k = 0; k < values.size(); ++k) at[sweep.poses.parameters[k]] = values[k];
    worst[column.name] = {{"value", json_number(column_value(sweep, column, *pose))},
                          {"unit", column.unit},
                          {"criterion", column.worst_is_largest ? "largest" : "smallest"},
                          {"pose", *pose},
                          {"csv_line", *pose + 2},
                          {"parameters", std::move(at)}};
  }
  summary["worst"] = std::move(worst);
  summary["threads"] = sweep.threads;
  summary["seconds"] = sweep.seconds;
  // Names come from the user's files, which may hold bytes that are not UTF-8.
  return summary.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

void write_sweep_csv(const SweepResult& sweep, bool full, const std::filesystem::path& file) {
  write_file_atomically(file, sweep_to_csv(sweep, full));
}

void write_sweep_summary(const SweepResult& sweep, bool full, const std::string& csv_file,
                         const std::filesystem::path& file) {
  write_file_atomically(file, sweep_summary_to_json(sweep, full, csv_file));
}

}  // namespace stiffmsa
