#include "stiffmsa/model.hpp"

#include <array>
#include <sstream>
#include <utility>

#include "model/suggest.hpp"

namespace stiffmsa {

std::string Diagnostic::to_string() const {
  std::ostringstream out;
  if (!location.file.empty()) {
    out << location.file;
    if (location.line > 0) {
      out << ':' << location.line;
      if (location.column > 0) out << ':' << location.column;
    }
    out << ": ";
  }
  if (!key_path.empty()) out << key_path << ": ";
  out << message;
  return out.str();
}

namespace {
std::string join_diagnostics(const std::vector<Diagnostic>& diagnostics) {
  std::string text = diagnostics.size() == 1
                         ? "invalid model: "
                         : "invalid model (" + std::to_string(diagnostics.size()) + " defects): ";
  for (std::size_t i = 0; i < diagnostics.size(); ++i) {
    if (i > 0) text += "; ";
    text += diagnostics[i].to_string();
  }
  return text;
}
}  // namespace

InputError::InputError(std::vector<Diagnostic> diagnostics)
    : Error(join_diagnostics(diagnostics)), diagnostics_(std::move(diagnostics)) {}

InputError::InputError(SourceLocation location, std::string key_path, std::string message)
    : InputError(std::vector<Diagnostic>{
          Diagnostic{std::move(location), std::move(key_path), std::move(message)}}) {}

namespace {
std::string summary_and_details(const std::string& summary,
                                const std::vector<std::string>& details) {
  std::string text = summary;
  for (const std::string& detail : details) text += "\n  " + detail;
  return text;
}
}  // namespace

SingularModelError::SingularModelError(Cause cause, std::string summary,
                                       std::vector<std::string> details)
    : Error(summary_and_details(summary, details)),
      cause_(cause),
      summary_(std::move(summary)),
      details_(std::move(details)) {}

namespace {
std::string no_such_name(const std::string& kind, const std::string& name,
                         const std::vector<std::string>& candidates) {
  return "there is no " + kind + " '" + name + "'" +
         (candidates.empty() ? "; there are none"
                             : detail::suggestion(name, candidates, "there are " + kind + "s"));
}
}  // namespace

NameError::NameError(std::string kind, std::string name, const std::vector<std::string>& candidates)
    : UsageError(no_such_name(kind, name, candidates)),
      kind_(std::move(kind)),
      name_(std::move(name)),
      suggestion_(detail::nearest(name_, candidates)) {}

NameError::NameError(std::string kind, std::string name, const std::vector<std::string>& candidates,
                     std::string message)
    : UsageError(std::move(message)),
      kind_(std::move(kind)),
      name_(std::move(name)),
      suggestion_(detail::nearest(name_, candidates)) {}

const KeyLocation* Origin::find(std::string_view key) const {
  for (auto it = key_locations.rbegin(); it != key_locations.rend(); ++it)
    if (it->key == key) return &*it;
  return nullptr;
}

SourceLocation Origin::of(std::string_view key) const {
  const KeyLocation* found = find(key);
  return found != nullptr ? SourceLocation{location.file, found->line, found->column} : location;
}

void Origin::record(std::string key, const SourceLocation& at) {
  key_locations.push_back({std::move(key), at.line, at.column});
}

Kinematics Kinematics::rigid() { return {}; }
Kinematics Kinematics::revolute(const Vec3& axis) {
  Kinematics k;
  k.type = JointType::revolute;
  k.axis = axis;
  return k;
}
Kinematics Kinematics::prismatic(const Vec3& axis) {
  Kinematics k = revolute(axis);
  k.type = JointType::prismatic;
  return k;
}
Kinematics Kinematics::cylindrical(const Vec3& axis) {
  Kinematics k = revolute(axis);
  k.type = JointType::cylindrical;
  return k;
}
Kinematics Kinematics::universal(const Vec3& a, const Vec3& b) {
  Kinematics k;
  k.type = JointType::universal;
  k.axis = a;
  k.axis_b = b;
  return k;
}
Kinematics Kinematics::spherical() {
  Kinematics k;
  k.type = JointType::spherical;
  return k;
}
Kinematics Kinematics::planar(const Vec3& normal) {
  Kinematics k;
  k.type = JointType::planar;
  k.normal = normal;
  return k;
}
Kinematics Kinematics::custom(std::vector<Vec6> rows) {
  Kinematics k;
  k.type = JointType::custom;
  k.free_rows = std::move(rows);
  return k;
}

int free_direction_count(const Kinematics& k) {
  switch (k.type) {
    case JointType::rigid: return 0;
    case JointType::revolute:
    case JointType::prismatic: return 1;
    case JointType::cylindrical:
    case JointType::universal: return 2;
    case JointType::spherical:
    case JointType::planar: return 3;
    case JointType::custom: return static_cast<int>(k.free_rows.size());
  }
  return 0;
}

namespace {
// A scalar stands for a 1×1 matrix or a single value: only where there is one free direction.
void require_one_direction(const Kinematics& kinematics, const char* what) {
  const int p = free_direction_count(kinematics);
  if (p != 1)
    throw UsageError(std::string("a scalar ") + what +
                     " is for a connection with one free direction; a " +
                     to_string(kinematics.type) + " one has " + std::to_string(p) + ": give " +
                     (what == std::string("stiffness") ? "a p×p matrix" : "p values"));
}
}  // namespace

Connection Connection::rigid() { return Connection(); }
Connection Connection::passive(Kinematics kinematics) {
  Connection c;
  c.kinematics = std::move(kinematics);
  return c;
}
Connection Connection::elastic(Kinematics kinematics, MatX stiffness) {
  Connection c = passive(std::move(kinematics));
  c.stiffness = std::move(stiffness);
  return c;
}
Connection Connection::elastic(Kinematics kinematics, double stiffness) {
  require_one_direction(kinematics, "stiffness");
  return elastic(std::move(kinematics), MatX::Constant(1, 1, stiffness));
}
Connection Connection::actuated(Kinematics kinematics) {
  Connection c = passive(std::move(kinematics));
  c.is_actuated = true;
  return c;
}
Connection Connection::actuated(Kinematics kinematics, MatX stiffness) {
  Connection c = elastic(std::move(kinematics), std::move(stiffness));
  c.is_actuated = true;
  return c;
}
Connection Connection::actuated(Kinematics kinematics, double stiffness) {
  Connection c = elastic(std::move(kinematics), stiffness);
  c.is_actuated = true;
  return c;
}
Connection Connection::preloaded(VecX values) const {
  Connection c = *this;
  c.preload = std::move(values);
  return c;
}
Connection Connection::preloaded(double value) const {
  require_one_direction(kinematics, "preload");
  return preloaded(VecX::Constant(1, value));
}

namespace {
std::vector<std::string> keys_of(const auto& named) {
  std::vector<std::string> keys;
  for (const auto& [key, value] : named) keys.push_back(key);
  return keys;
}
}  // namespace

void Model::add_material(std::string material_name, const Material& material) {
  if (materials.contains(material_name))
    throw UsageError("the material '" + material_name + "' is defined already");
  materials.emplace(std::move(material_name), material);
}
void Model::add_section(std::string section_name, const Section& section) {
  if (sections.contains(section_name))
    throw UsageError("the section '" + section_name + "' is defined already");
  sections.emplace(std::move(section_name), section);
}

PointIndex Model::add_point(std::string point_name, const Vec3& position) {
  points.push_back(Point{std::move(point_name), position, {}});
  return {points.size() - 1};
}

namespace {
LinkIndex push_link(Model& m, std::string name, std::string from, std::string to, LinkKind kind) {
  m.links.push_back(Link{std::move(name), std::move(from), std::move(to), std::move(kind), {}});
  return {m.links.size() - 1};
}
}  // namespace

LinkIndex Model::add_beam(std::string link_name, std::string from, std::string to,
                          const Material& material, const Section& section) {
  return push_link(*this, std::move(link_name), std::move(from), std::move(to),
                   BeamLink{material, section, false, std::nullopt});
}
LinkIndex Model::add_beam(std::string link_name, std::string from, std::string to,
                          std::string_view material_name, std::string_view section_name) {
  return add_beam(std::move(link_name), std::move(from), std::move(to), material(material_name),
                  section(section_name));
}
const Material& Model::material(std::string_view material_name) const {
  const auto found = materials.find(material_name);
  if (found == materials.end())
    throw NameError("material", std::string(material_name), keys_of(materials));
  return found->second;
}
const Section& Model::section(std::string_view section_name) const {
  const auto found = sections.find(section_name);
  if (found == sections.end())
    throw NameError("section", std::string(section_name), keys_of(sections));
  return found->second;
}
LinkIndex Model::add_rigid_link(std::string link_name, std::string from, std::string to) {
  return push_link(*this, std::move(link_name), std::move(from), std::move(to), RigidLink{});
}
LinkIndex Model::add_matrix_link(std::string link_name, std::string from, std::string to,
                                 const Mat12& K, LinkFrame frame) {
  return push_link(*this, std::move(link_name), std::move(from), std::move(to),
                   MatrixLink{K, frame, std::nullopt});
}
LinkIndex Model::add_compliance_link(std::string link_name, std::string from, std::string to,
                                     const Mat6& C, LinkFrame frame) {
  return push_link(*this, std::move(link_name), std::move(from), std::move(to),
                   ComplianceLink{C, frame, std::nullopt});
}
JointIndex Model::add_joint(std::string joint_name, std::string at,
                            std::vector<std::string> link_names, Connection connection) {
  joints.push_back(Joint{
      std::move(joint_name), std::move(at), std::move(link_names), std::move(connection), {}});
  return {joints.size() - 1};
}
SupportIndex Model::add_support(std::string support_name, std::string at,
                                std::vector<std::string> link_names, Connection connection) {
  supports.push_back(Support{std::move(support_name),
                             std::move(at),
                             std::move(link_names),
                             std::move(connection),
                             {},
                             std::nullopt});
  return {supports.size() - 1};
}
LoadIndex Model::add_load(std::string at, std::optional<std::string> link, const Vec6& wrench) {
  loads.push_back(Load{std::move(at), std::move(link), wrench, false, {}});
  return {loads.size() - 1};
}
LinkLoadIndex Model::add_link_load(std::string link_name, const DistributedLinkLoad& load) {
  link_loads.push_back(LinkLoad{std::move(link_name), load, {}});
  return {link_loads.size() - 1};
}
LinkLoadIndex Model::add_link_load(std::string link_name, const PointLinkLoad& load) {
  link_loads.push_back(LinkLoad{std::move(link_name), load, {}});
  return {link_loads.size() - 1};
}
LoadCaseIndex Model::add_load_case(LoadCase load_case) {
  load_cases.push_back(std::move(load_case));
  return {load_cases.size() - 1};
}
EndEffectorIndex Model::add_end_effector(std::string end_effector_name, std::string at,
                                         std::optional<std::string> link) {
  end_effectors.push_back(
      EndEffector{std::move(end_effector_name), std::move(at), std::move(link), std::nullopt, {}});
  return {end_effectors.size() - 1};
}

const Point* Model::find_point(const std::string& name) const {
  for (const auto& p : points)
    if (p.name == name) return &p;
  return nullptr;
}
const Link* Model::find_link(const std::string& name) const {
  for (const auto& l : links)
    if (l.name == name) return &l;
  return nullptr;
}

namespace {
constexpr std::array<std::pair<JointType, const char*>, 8> kJointTypeNames{{
    {JointType::rigid, "rigid"},
    {JointType::revolute, "revolute"},
    {JointType::prismatic, "prismatic"},
    {JointType::cylindrical, "cylindrical"},
    {JointType::universal, "universal"},
    {JointType::spherical, "spherical"},
    {JointType::planar, "planar"},
    {JointType::custom, "custom"},
}};
constexpr std::array<std::pair<SectionShape, const char*>, 5> kShapeNames{{
    {SectionShape::circle, "circle"},
    {SectionShape::tube, "tube"},
    {SectionShape::rect, "rect"},
    {SectionShape::rect_tube, "rect_tube"},
    {SectionShape::generic, "generic"},
}};

template <class Enum, std::size_t N>
const char* name_of(const std::array<std::pair<Enum, const char*>, N>& table, Enum value) {
  for (const auto& [e, name] : table)
    if (e == value) return name;
  return "?";
}
template <class Enum, std::size_t N>
std::optional<Enum> value_of(const std::array<std::pair<Enum, const char*>, N>& table,
                             const std::string& text) {
  for (const auto& [e, name] : table)
    if (text == name) return e;
  return std::nullopt;
}
}  // namespace

const char* to_string(JointType t) { return name_of(kJointTypeNames, t); }
std::optional<JointType> joint_type_from_string(const std::string& s) {
  return value_of(kJointTypeNames, s);
}
const char* to_string(SectionShape s) { return name_of(kShapeNames, s); }
std::optional<SectionShape> section_shape_from_string(const std::string& s) {
  return value_of(kShapeNames, s);
}
const char* to_string(LinkEnd e) { return e == LinkEnd::from ? "from" : "to"; }

const char* to_string(AnalysisMode mode) {
  return mode == AnalysisMode::linear ? "linear" : "loaded";
}
std::optional<AnalysisMode> analysis_mode_from_string(std::string_view name) {
  if (name == "linear") return AnalysisMode::linear;
  if (name == "loaded") return AnalysisMode::loaded;
  return std::nullopt;
}

}  // namespace stiffmsa
