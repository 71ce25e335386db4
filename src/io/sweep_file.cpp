#include "stiffmsa/io/sweep_file.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/plain_number.hpp"
#include "stiffmsa/io/result_file.hpp"
#include "stiffmsa/number_text.hpp"

namespace stiffmsa {

std::optional<double> parse_plain_number(std::string_view text) {
  return detail::plain_number(text);
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr const auto& kStatuses = kPoseStatuses;

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

const char* const kMeasureNames[] = {"k_trans_min", "k_trans_max",      "k_rot_min",
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
  const auto defect = [&](std::size_t line, int column, const std::string& key,
                          std::string message) {
    defects.push_back({{file_name, static_cast<int>(line), column}, key, std::move(message)});
  };
  while (start <= text.size()) {
    const auto end = text.find('\n', start);
    const std::string_view line =
        text.substr(start, end == std::string_view::npos ? text.npos : end - start);
    start = end == std::string_view::npos ? text.size() + 1 : end + 1;
    ++line_number;
    const std::string content = trimmed(line);
    if (content.empty() || content[0] == '#') continue;
    auto fields = split_fields(line);
    if (table.parameters.empty()) {
      for (std::size_t k = 0; k < fields.size(); ++k) {
        if (fields[k].empty())
          defect(line_number, 0, "",
                 "column " + std::to_string(k + 1) + " of the header has no parameter name");
        for (std::size_t j = 0; j < k; ++j)
          if (!fields[k].empty() && fields[j] == fields[k])
            defect(line_number, 0, fields[k],
                   "the parameter '" + fields[k] + "' heads two columns");
      }
      table.parameters = std::move(fields);
      continue;
    }
    if (fields.size() != table.parameters.size()) {
      defect(line_number, 0, "",
             "expected " + counted(table.parameters.size(), "value") +
                 " (one per parameter of the header), got " + std::to_string(fields.size()));
      continue;
    }
    for (std::size_t k = 0; k < fields.size(); ++k) {
      const auto value = detail::plain_number(fields[k]);
      if (!value)
        defect(line_number, 0, table.parameters[k],
               "expected a finite number, got '" + fields[k] + "'");
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
      columns.push_back({effector + "." + kMeasureNames[q], kMeasureUnits[q],
                         static_cast<SweepQuantity>(q), e, 0, 0,
                         q >= static_cast<int>(SweepQuantity::deflection_trans)});
    columns.push_back({effector + ".cond_trans", "", SweepQuantity::cond_trans, e, 0, 0, true});
    if (sweep.direction) {
      columns.push_back(
          {effector + ".k_trans_dir", "N/m", SweepQuantity::k_trans_dir, e, 0, 0, false});
      columns.push_back(
          {effector + ".k_rot_dir", "N·m/rad", SweepQuantity::k_rot_dir, e, 0, 0, false});
    }
    if (!full) continue;
    for (const auto& [quantity, letter] :
         {std::pair{SweepQuantity::compliance, 'C'}, std::pair{SweepQuantity::stiffness, 'K'}})
      for (int row = 0; row < 6; ++row)
        for (int col = 0; col < 6; ++col)
          columns.push_back(
              {effector + "." + letter + std::to_string(row + 1) + std::to_string(col + 1),
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
  if (result.status != PoseStatus::ok || column.end_effector >= result.end_effectors.size())
    return kNaN;
  const EndEffectorMeasures& m = result.end_effectors[column.end_effector];
  switch (column.quantity) {
    case SweepQuantity::k_trans_min: return m.principal.translational(0);
    case SweepQuantity::k_trans_max: return m.principal.translational(2);
    case SweepQuantity::k_rot_min: return m.principal.rotational(0);
    case SweepQuantity::k_rot_max: return m.principal.rotational(2);
    case SweepQuantity::deflection_trans: return m.deflection_translation;
    case SweepQuantity::deflection_rot: return m.deflection_rotation;
    case SweepQuantity::compliance:
      return m.compliance ? (*m.compliance)(column.row, column.col) : kNaN;
    case SweepQuantity::stiffness:
      return m.stiffness ? (*m.stiffness)(column.row, column.col) : kNaN;
    case SweepQuantity::cond_trans: return m.principal.translational_condition();
    case SweepQuantity::k_trans_dir:
      return m.along_direction ? m.along_direction->translational : kNaN;
    case SweepQuantity::k_rot_dir: return m.along_direction ? m.along_direction->rotational : kNaN;
  }
  return kNaN;
}

bool is_worse(const SweepColumn& column, double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return !std::isnan(a) && std::isnan(b);
  if (column.quantity == SweepQuantity::compliance || column.quantity == SweepQuantity::stiffness) {
    a = std::abs(a);
    b = std::abs(b);
  }
  return column.worst_is_largest ? a > b : a < b;
}

std::optional<std::size_t> worst_pose(const SweepResult& sweep, const SweepColumn& column) {
  std::optional<std::size_t> worst;
  double worst_value = kNaN;
  for (std::size_t pose = 0; pose < sweep.results.size(); ++pose) {
    const double value = column_value(sweep, column, pose);
    if (is_worse(column, value, worst_value)) {
      worst = pose;
      worst_value = value;
    }
  }
  return worst;
}

SweepRows sweep_rows(const SweepResult& sweep, const std::vector<SweepColumn>& columns,
                     std::size_t first_pose) {
  SweepRows rows;
  rows.first_pose = first_pose;
  rows.parameter_count = sweep.poses.parameters.size();
  rows.column_count = columns.size();
  const std::size_t count = sweep.results.size();
  rows.parameters.assign(
      sweep.poses.values.begin(),
      sweep.poses.values.begin() + static_cast<std::ptrdiff_t>(count * rows.parameter_count));
  rows.statuses.reserve(count);
  rows.messages.reserve(count);
  rows.large_deflections.reserve(count);
  rows.values.reserve(count * columns.size());
  for (std::size_t pose = 0; pose < count; ++pose) {
    rows.statuses.push_back(sweep.results[pose].status);
    rows.messages.push_back(sweep.results[pose].message);
    rows.large_deflections.push_back(sweep.results[pose].large_deflection ? 1 : 0);
    for (const auto& column : columns) rows.values.push_back(column_value(sweep, column, pose));
  }
  return rows;
}

std::string sweep_csv_header(const std::vector<std::string>& parameters,
                             const std::vector<SweepColumn>& columns) {
  std::string out;
  for (const auto& p : parameters) {
    append_text(out, p);
    out += ',';
  }
  out += "status,message";
  for (const auto& c : columns) {
    out += ',';
    append_text(out, c.name);
  }
  out += '\n';
  return out;
}

void append_sweep_csv_rows(std::string& out, const SweepRows& rows) {
  for (std::size_t row = 0; row < rows.size(); ++row) {
    for (double value : rows.pose(row)) {
      append_number(out, value);
      out += ',';
    }
    out += to_string(rows.statuses[row]);
    out += ',';
    append_text(out, rows.messages[row]);
    for (std::size_t column = 0; column < rows.column_count; ++column) {
      out += ',';
      append_number(out, rows.value(row, column));
    }
    out += '\n';
  }
}

std::string sweep_to_csv(const SweepResult& sweep, bool full) {
  const auto columns = sweep_columns(sweep, full);
  std::string out = sweep_csv_header(sweep.poses.parameters, columns);
  append_sweep_csv_rows(out, sweep_rows(sweep, columns));
  return out;
}

std::optional<PoseStatus> pose_status_from_string(std::string_view name) {
  for (auto status : kStatuses)
    if (name == to_string(status)) return status;
  return std::nullopt;
}

SweepSummary::SweepSummary(std::vector<SweepColumn> columns)
    : columns_(std::move(columns)), worst_(columns_.size()) {}

void SweepSummary::offer_worst(std::size_t column, Pose candidate) {
  auto& worst = worst_[column];
  if (!worst || is_worse(columns_[column], candidate.value, worst->value) ||
      (!is_worse(columns_[column], worst->value, candidate.value) &&
       candidate.index < worst->index))
    worst = std::move(candidate);
}

void SweepSummary::offer_first(std::optional<Pose>& first, Pose candidate) {
  if (!first || candidate.index < first->index) first = std::move(candidate);
}

void SweepSummary::add(const SweepRows& rows) {
  poses_ += rows.size();
  // The block's own first failure and worst rows first, then one offer each: a pass over the
  // block costs a comparison per value, not a copy of its parameters.
  std::optional<std::size_t> block_failed, block_large_deflection;
  std::vector<std::optional<std::size_t>> block_worst(columns_.size());
  for (std::size_t row = 0; row < rows.size(); ++row) {
    ++counts_[static_cast<std::size_t>(rows.statuses[row])];
    if (rows.statuses[row] != PoseStatus::ok && !block_failed) block_failed = row;
    if (rows.large_deflections[row] != 0) {
      ++large_deflections_;
      if (!block_large_deflection) block_large_deflection = row;
    }
    for (std::size_t column = 0; column < columns_.size(); ++column)
      if (is_worse(columns_[column], rows.value(row, column),
                   block_worst[column] ? rows.value(*block_worst[column], column) : kNaN))
        block_worst[column] = row;
  }
  const auto pose_of = [&](std::size_t row, double value) {
    const bool told = rows.statuses[row] != PoseStatus::ok || rows.large_deflections[row] != 0;
    return Pose{rows.first_pose + row,
                {rows.pose(row).begin(), rows.pose(row).end()},
                value,
                rows.statuses[row],
                told ? rows.messages[row] : std::string()};
  };
  if (block_failed) offer_first(first_failed_, pose_of(*block_failed, kNaN));
  if (block_large_deflection)
    offer_first(first_large_deflection_, pose_of(*block_large_deflection, kNaN));
  for (std::size_t column = 0; column < columns_.size(); ++column)
    if (const auto row = block_worst[column])
      offer_worst(column, pose_of(*row, rows.value(*row, column)));
}

void SweepSummary::add(const SweepSummary& other) {
  poses_ += other.poses_;
  for (std::size_t k = 0; k < counts_.size(); ++k) counts_[k] += other.counts_[k];
  for (std::size_t column = 0; column < columns_.size() && column < other.worst_.size(); ++column)
    if (other.worst_[column]) offer_worst(column, *other.worst_[column]);
  if (other.first_failed_) offer_first(first_failed_, *other.first_failed_);
  large_deflections_ += other.large_deflections_;
  if (other.first_large_deflection_)
    offer_first(first_large_deflection_, *other.first_large_deflection_);
}

namespace {

void put_size(std::string& out, std::size_t value) {
  const auto v = static_cast<std::uint64_t>(value);
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

void put_double(std::string& out, double value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

void put_pose(std::string& out, const SweepSummary::Pose& pose) {
  put_size(out, pose.index);
  put_size(out, pose.parameters.size());
  for (double v : pose.parameters) put_double(out, v);
  put_double(out, pose.value);
  put_size(out, static_cast<std::size_t>(pose.status));
  put_size(out, pose.message.size());
  out += pose.message;
}

// Reads what put_* wrote; a short or inconsistent buffer is an internal error between ranks.
class Unpacker {
 public:
  explicit Unpacker(std::string_view bytes) : bytes_(bytes) {}
  std::size_t size() {
    std::uint64_t v = 0;
    take(&v, sizeof v);
    return static_cast<std::size_t>(v);
  }
  double number() {
    double v = 0;
    take(&v, sizeof v);
    return v;
  }
  std::string text(std::size_t length) {
    if (length > bytes_.size()) throw Error("sweep data passed between processes is truncated");
    std::string t(bytes_.substr(0, length));
    bytes_.remove_prefix(length);
    return t;
  }
  SweepSummary::Pose pose() {
    SweepSummary::Pose p;
    p.index = size();
    p.parameters.resize(size());
    for (double& v : p.parameters) v = number();
    p.value = number();
    const std::size_t status = size();
    if (status >= kStatuses.size())
      throw Error("a sweep summary passed between processes has an unknown status");
    p.status = static_cast<PoseStatus>(status);
    p.message = text(size());
    return p;
  }

 private:
  void take(void* out, std::size_t n) {
    if (n > bytes_.size()) throw Error("sweep data passed between processes is truncated");
    std::memcpy(out, bytes_.data(), n);
    bytes_.remove_prefix(n);
  }
  std::string_view bytes_;
};

}  // namespace

void serialize_rows(std::string& out, const SweepRows& rows) {
  put_size(out, rows.first_pose);
  put_size(out, rows.parameter_count);
  put_size(out, rows.column_count);
  put_size(out, rows.size());
  put_size(out, rows.parameters.size());
  for (double v : rows.parameters) put_double(out, v);
  for (auto status : rows.statuses) put_size(out, static_cast<std::size_t>(status));
  put_size(out, rows.large_deflections.size());
  out.append(reinterpret_cast<const char*>(rows.large_deflections.data()),
             rows.large_deflections.size());
  put_size(out, rows.messages.size());
  for (const auto& message : rows.messages) {
    put_size(out, message.size());
    out += message;
  }
  put_size(out, rows.values.size());
  for (double v : rows.values) put_double(out, v);
}

SweepRows deserialize_rows(std::string_view bytes) {
  Unpacker in(bytes);
  SweepRows rows;
  rows.first_pose = in.size();
  rows.parameter_count = in.size();
  rows.column_count = in.size();
  const std::size_t count = in.size();
  rows.parameters.resize(in.size());
  for (double& v : rows.parameters) v = in.number();
  for (std::size_t row = 0; row < count; ++row) {
    const std::size_t status = in.size();
    if (status >= kStatuses.size())
      throw Error("sweep rows passed between processes have an unknown status");
    rows.statuses.push_back(static_cast<PoseStatus>(status));
  }
  const std::string flags = in.text(in.size());
  rows.large_deflections.assign(flags.begin(), flags.end());
  rows.messages.resize(in.size());
  for (auto& message : rows.messages) message = in.text(in.size());
  rows.values.resize(in.size());
  for (double& v : rows.values) v = in.number();
  return rows;
}

std::string SweepSummary::serialize() const {
  std::string out;
  put_size(out, poses_);
  for (std::size_t count : counts_) put_size(out, count);
  put_size(out, worst_.size());
  for (const auto& worst : worst_) {
    put_size(out, worst ? 1 : 0);
    if (worst) put_pose(out, *worst);
  }
  put_size(out, first_failed_ ? 1 : 0);
  if (first_failed_) put_pose(out, *first_failed_);
  put_size(out, large_deflections_);
  put_size(out, first_large_deflection_ ? 1 : 0);
  if (first_large_deflection_) put_pose(out, *first_large_deflection_);
  return out;
}

SweepSummary SweepSummary::deserialize(std::vector<SweepColumn> columns, std::string_view bytes) {
  SweepSummary summary(std::move(columns));
  Unpacker in(bytes);
  summary.poses_ = in.size();
  for (std::size_t& count : summary.counts_) count = in.size();
  if (in.size() != summary.worst_.size())
    throw Error("a sweep summary passed between processes has other columns");
  for (auto& worst : summary.worst_)
    if (in.size() != 0) worst = in.pose();
  if (in.size() != 0) summary.first_failed_ = in.pose();
  summary.large_deflections_ = in.size();
  if (in.size() != 0) summary.first_large_deflection_ = in.pose();
  return summary;
}

SweepCsvReader::SweepCsvReader(const std::filesystem::path& file,
                               std::vector<std::string> parameters,
                               std::vector<SweepColumn> columns)
    : name_(file.string()),
      in_(file, std::ios::binary),
      parameters_(std::move(parameters)),
      columns_(std::move(columns)) {
  std::error_code error;
  if (!in_ || std::filesystem::is_directory(file, error))
    throw IoError("cannot read the sweep rows '" + name_ + "'");
  std::string header;
  const std::string expected = sweep_csv_header(parameters_, columns_);
  if (!next_record(header) || header + '\n' != expected)
    throw InputError({name_, 1, 0}, "",
                     "the header is not the one this sweep writes (" +
                         expected.substr(0, expected.size() - 1) + ")");
}

bool SweepCsvReader::next_record(std::string& record) {
  record.clear();
  std::string line;
  std::size_t quotes = 0;
  while (std::getline(in_, line)) {
    ++line_;
    quotes += static_cast<std::size_t>(std::count(line.begin(), line.end(), '"'));
    record += line;
    if (quotes % 2 == 0) return true;
    record += '\n';  // a quoted field goes on on the next line
  }
  if (in_.bad()) throw IoError("cannot read the sweep rows '" + name_ + "'");
  return !record.empty();
}

SweepRows SweepCsvReader::read(std::size_t first_pose, std::size_t count) {
  SweepRows rows;
  rows.first_pose = first_pose;
  rows.parameter_count = parameters_.size();
  rows.column_count = columns_.size();
  std::string record;
  const std::size_t fields_per_row = parameters_.size() + 2 + columns_.size();
  while (rows.size() < count && next_record(record)) {
    const auto defect = [&](const std::string& key, const std::string& message) {
      return InputError({name_, static_cast<int>(line_), 0}, key, message);
    };
    const auto fields = split_fields(record);
    if (fields.size() != fields_per_row)
      throw defect("", "expected " + std::to_string(fields_per_row) + " fields, got " +
                           std::to_string(fields.size()) + " (a row cut short?)");
    const auto number = [&](const std::string& text, const std::string& key, bool may_be_empty) {
      if (text.empty() && may_be_empty) return kNaN;
      if (text == "inf" || text == "-inf") return text[0] == '-' ? -kInfinity : kInfinity;
      const auto value = detail::plain_number(text);
      if (!value) throw defect(key, "expected a number, got '" + text + "'");
      return *value;
    };
    for (std::size_t k = 0; k < parameters_.size(); ++k)
      rows.parameters.push_back(number(fields[k], parameters_[k], false));
    const auto status = pose_status_from_string(fields[parameters_.size()]);
    if (!status)
      throw defect("status", "'" + fields[parameters_.size()] + "' is not a pose status");
    rows.statuses.push_back(*status);
    rows.messages.push_back(fields[parameters_.size() + 1]);
    rows.large_deflections.push_back(*status == PoseStatus::ok &&
                                     rows.messages.back().starts_with(kLargeDeflectionWarning));
    for (std::size_t c = 0; c < columns_.size(); ++c)
      rows.values.push_back(number(fields[parameters_.size() + 2 + c], columns_[c].name, true));
  }
  rows_read_ += rows.size();
  return rows;
}

std::string sweep_summary_to_json(const SweepResult& sweep, bool full,
                                  const std::string& csv_file) {
  SweepSummary summary(sweep_columns(sweep, full));
  summary.add(sweep_rows(sweep, summary.columns()));
  return sweep_summary_to_json(sweep, full, summary, csv_file);
}

std::string sweep_summary_to_json(const SweepResult& run, bool full, const SweepSummary& summary,
                                  const std::string& csv_file, std::size_t csv_first_pose) {
  using nlohmann::json;
  json out;
  out["format"] = "stiffmsa-sweep/1";
  out["model"] = run.model;
  if (!csv_file.empty()) out["csv"] = csv_file;
  out["poses"] = summary.poses();
  json parameters = json::array();
  for (std::size_t k = 0; k < run.poses.parameters.size(); ++k) {
    json p{{"name", run.poses.parameters[k]}, {"unit", k < run.units.size() ? run.units[k] : ""}};
    for (const auto& axis : run.poses.grid)
      if (axis.parameter == run.poses.parameters[k])
        p["grid"] = {{"start", axis.start}, {"stop", axis.stop}, {"count", axis.count}};
    parameters.push_back(std::move(p));
  }
  out["parameters"] = std::move(parameters);
  json fixed = json::object();
  for (const ParameterValue& p : run.fixed_parameters)
    fixed[p.name] = {{"value", p.value}, {"unit", p.unit}, {"set", p.set}};
  out["fixed_parameters"] = std::move(fixed);
  if (run.direction)
    out["direction"] = {(*run.direction)(0), (*run.direction)(1), (*run.direction)(2)};
  out["end_effectors"] = run.end_effectors;
  out["full"] = full;
  json counts;
  for (auto status : kStatuses) counts[to_string(status)] = summary.count(status);
  out["status"] = std::move(counts);
  out["large_deflection"] = summary.large_deflections();
  out["warnings"] = run.warnings;
  json worst = json::object();
  for (std::size_t c = 0; c < summary.columns().size(); ++c) {
    const SweepColumn& column = summary.columns()[c];
    const auto& pose = summary.worst(c);
    if (!pose) {
      worst[column.name] = nullptr;
      continue;
    }
    json at = json::object();
    for (std::size_t k = 0; k < pose->parameters.size() && k < run.poses.parameters.size(); ++k)
      at[run.poses.parameters[k]] = pose->parameters[k];
    worst[column.name] = {{"value", json_number(pose->value)},
                          {"unit", column.unit},
                          {"criterion", column.worst_is_largest ? "largest" : "smallest"},
                          {"pose", pose->index},
                          {"csv_line", pose->index - csv_first_pose + 2},
                          {"parameters", std::move(at)}};
  }
  out["worst"] = std::move(worst);
  out["threads"] = run.threads;
  out["seconds"] = run.seconds;
  // Names come from the user's files, which may hold bytes that are not UTF-8.
  return out.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

void write_sweep_csv(const SweepResult& sweep, bool full, const std::filesystem::path& file) {
  write_file_atomically(file, sweep_to_csv(sweep, full));
}

void write_sweep_summary(const SweepResult& sweep, bool full, const std::string& csv_file,
                         const std::filesystem::path& file) {
  write_file_atomically(file, sweep_summary_to_json(sweep, full, csv_file));
}

}  // namespace stiffmsa
